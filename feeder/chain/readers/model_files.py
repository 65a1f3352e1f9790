"""The files a model names, kept inside the model's folder.

A model names other files: a URDF its meshes (``package://``, ``file://`` or relative paths,
:func:`~feeder.chain.readers.urdf.mesh_path`), a mesh its own files (an OBJ's material
libraries, read by assimp; a COLLADA file's images, which Pinocchio's MeshCat viewer embeds in
the page). Each is resolved (``..`` and symbolic links followed) and read only if it lies inside
the folder of the model file: a model is shipped as a folder, and ``package:///NAME`` means
"beside the model", so a name that leads out of it (``package:///../secret.stl``, a link to
``/etc``) is a mistake or an attempt to put another file into a report page, and that file is
never opened. MJCF and SDF models need no other file: Pinocchio's MJCF parser builds the model
without opening its meshes, the SDF reader drops visuals, and both are drawn as stick figures.
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from ...exceptions import ModelFolderError, UrdfError

_COLLADA = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)


def inside_folder(path: Path, folder: Path, what: str) -> Path:
    """``path`` (relative to ``folder``, or absolute) resolved, if it lies inside ``folder``.

    Raises:
        ModelFolderError: It lies outside (``what`` names it in the message).
        UrdfError: Its symbolic links form a loop.
    """
    try:
        resolved = (folder / path).resolve()
    except (OSError, RuntimeError) as exc:  # a loop of links (RuntimeError before 3.13)
        raise UrdfError(f"{what} cannot be resolved: {exc}") from None
    if not resolved.is_relative_to(folder.resolve()):
        raise ModelFolderError(
            f"{what} lies outside the model's folder {folder} (it resolves to {resolved}): "
            "not read; copy the file into that folder"
        )
    return resolved


def mesh_references(mesh: Path) -> list[Path]:
    """The files the mesh file ``mesh`` names, as its readers find them (relative to its
    folder): an OBJ's ``mtllib`` lines, a COLLADA file's ``<init_from>`` images. An STL names
    none, nor does a COLLADA file that is not XML (it fails to load later).

    Raises:
        OSError: The file cannot be read.
    """
    suffix = mesh.suffix.lower()
    names: list[str] = []
    if suffix == ".obj":
        for line in mesh.read_text(encoding="utf-8", errors="replace").splitlines():
            keyword, *rest = line.split(None, 1)
            if keyword == "mtllib" and rest:  # one name, or several (assimp reads either way)
                names += [rest[0].strip(), *rest[0].split()]
    elif suffix == ".dae":
        try:
            root = etree.parse(str(mesh), _COLLADA).getroot()
        except etree.XMLSyntaxError:
            return []
        names = [
            (element.text or "").strip()
            for element in root.iter()
            if isinstance(element.tag, str)
            and etree.QName(element).localname in ("init_from", "ref")
        ]
    return [mesh.parent / name for name in dict.fromkeys(names) if name]
