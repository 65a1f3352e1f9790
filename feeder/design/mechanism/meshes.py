"""The mesh files of a mechanism's model, copied beside its written optimum.

A URDF names its meshes relative to its own folder, and feeder reads a model's files only
inside that folder (:mod:`feeder.chain.readers.model_files`): the optimum written into an
output folder could read none of the meshes beside the original model. The loads need no
meshes (the design points run without them), but ``feeder view`` and the report pages of the
written model draw them, so ``feeder design optimize`` copies them:

* each mesh file that a ``<visual>`` or ``<collision>`` names and the model's readers accept
  (:func:`~feeder.chain.readers.urdf.mesh_path`: found, inside the model's folder after
  ``..`` and links), with the files it names itself (an OBJ's material libraries, a COLLADA
  file's images, :func:`~feeder.chain.readers.model_files.mesh_references`) that lie inside the
  folder too, goes to :data:`MESH_FOLDER` of the output folder at its path relative to the
  model's folder (so a mesh's own references still resolve), each file atomically;
* the optimum's ``filename`` attributes name the copies (``meshes/part.stl``, relative to it);
* a mesh the model's readers refuse (not found, outside the folder) is neither copied nor
  renamed: ``feeder analyze`` of the written model warns about it as it does for the model;
* the copies total at most :data:`MESH_LIMIT` bytes, a model naming more refused in one line
  before any run.
"""

from __future__ import annotations

import os
import shutil
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from ...chain.readers.model_files import inside_folder, mesh_references
from ...chain.readers.urdf import mesh_path
from ...exceptions import InputError, ModelFolderError, UrdfError
from ...files import Writer, atomic_path
from .urdf_edit import parse

MESH_FOLDER = "meshes"
"""The folder of the output folder that holds the optimum's meshes."""

MESH_LIMIT = 256 * 2**20
"""The largest total size of the mesh files copied beside an optimum [bytes] (256 MiB: CAD
exports of a mechanism are a few MiB; more is a model to simplify, not one to copy per run)."""


@dataclass(frozen=True)
class MeshCopies:
    """The mesh files to copy beside the optimum and its URDF's new mesh names.

    Attributes:
        files: Output name (``meshes/…``, ``/``-separated) → the file to copy there.
        names: A mesh ``filename`` of the model → the copy's name, relative to the optimum.
    """

    files: dict[str, Path]
    names: dict[str, str]

    def writers(self) -> dict[str, Writer]:
        """Output name → the writer copying its file atomically."""
        return {name: _copier(source) for name, source in self.files.items()}

    def rewritten(self, urdf: str) -> str:
        """The URDF text ``urdf`` with its meshes' ``filename`` naming the copies."""
        if not self.names:
            return urdf
        root = ET.fromstring(urdf)
        for mesh in _meshes(root):
            if mesh.get("filename") in self.names:
                mesh.set("filename", self.names[mesh.get("filename")])
        return ET.tostring(root, encoding="unicode", xml_declaration=True)


def mesh_copies(model: Path, urdf: str, limit: int = MESH_LIMIT) -> MeshCopies:
    """The copies of the meshes the URDF ``urdf`` (the text of the file ``model``) names
    (module docstring).

    Raises:
        InputError: The files total more than ``limit`` bytes; the URDF is not XML.
    """
    folder = model.parent.resolve()
    files: dict[str, Path] = {}
    names: dict[str, str] = {}
    for mesh in _meshes(parse(urdf, str(model))):
        uri = mesh.get("filename")
        if uri is None or uri in names:
            continue
        try:
            path = mesh_path(uri, model)
        except (ModelFolderError, UrdfError):
            continue  # refused as the model's readers refuse it (module docstring)
        names[uri] = _add(files, path.relative_to(folder), path)
        for relative, source in _references(path, folder):
            _add(files, relative, source)
    size = sum(source.stat().st_size for source in files.values())
    if size > limit:
        raise InputError(
            f"{model}: its {len(files)} mesh files total {size / 2**20:.1f} MiB, more than the "
            f"{limit / 2**20:.0f} MiB that optimize copies beside the optimum: simplify the "
            "meshes or remove the visuals"
        )
    return MeshCopies(files, names)


def _meshes(root: ET.Element) -> list[ET.Element]:
    """The ``<mesh>`` elements of the bodies' visuals and collisions."""
    return [
        mesh
        for owner in root.iter()
        if owner.tag in ("visual", "collision")
        for mesh in owner.iter("mesh")
    ]


def _add(files: dict[str, Path], relative: Path, source: Path) -> str:
    """Record the copy of the file ``source`` named ``relative`` in the model's folder; the
    copy's output name."""
    name = str(PurePosixPath(MESH_FOLDER, *relative.parts))
    files.setdefault(name, source)
    return name


def _references(mesh: Path, folder: Path) -> list[tuple[Path, Path]]:
    """The files the mesh file ``mesh`` names that lie inside ``folder``: each as the copied
    mesh names it (its own relative name, normalised, relative to ``folder``) and where it is."""
    try:
        references = mesh_references(mesh)
    except OSError:
        return []  # unreadable: the viewer leaves it out, and reads no file it names
    found = []
    for reference in references:
        try:
            resolved = inside_folder(reference, folder, f"file {reference.name!r}")
        except (ModelFolderError, UrdfError):
            continue
        relative = Path(os.path.normpath(os.path.relpath(reference, folder)))
        if resolved.is_file() and relative.parts[0] != "..":
            found.append((relative, resolved))
    return found


def _copier(source: Path) -> Writer:
    def write(path: Path) -> None:
        with atomic_path(path) as temporary:
            shutil.copyfile(source, temporary)

    return write
