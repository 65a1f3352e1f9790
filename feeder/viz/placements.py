"""Where a scene's parts are over the motion: homogeneous transforms, the joints' and the visual
geometries' placements at every sample, the base's placements in the level axes, and the spheres
around the bodies that the camera frames (centres, radii, their box)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..chain.results import BaseState


def homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """The 4 × 4 homogeneous transform of a rotation (3, 3) and a translation (3,)."""
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def y_onto(direction: np.ndarray) -> np.ndarray:
    """A rotation (3, 3) turning the y axis onto the unit vector ``direction``."""
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(y, direction)
    sine, cosine = np.linalg.norm(axis), float(y @ direction)
    if sine < 1e-9:
        return np.eye(3) if cosine > 0.0 else np.diag([1.0, -1.0, -1.0])
    return pin.AngleAxis(math.atan2(sine, cosine), axis / sine).matrix()


def up_of(gravity: np.ndarray) -> np.ndarray:
    """The unit "up" vector (3,) against ``gravity`` [m/s²]: z (URDF's convention) without
    gravity."""
    norm = float(np.linalg.norm(gravity))
    return -np.asarray(gravity) / norm if norm > 0.0 else np.array([0.0, 0.0, 1.0])


def joint_placements(model: pin.Model, q: np.ndarray) -> np.ndarray:
    """World placements (N, njoints, 4, 4) of every joint at the poses q (N, nq): one forward
    kinematics pass per pose, from which the geometries' and frames' placements follow."""
    data = model.createData()
    out = np.empty((len(q), model.njoints, 4, 4))
    for k, q_k in enumerate(q):
        pin.forwardKinematics(model, data, q_k)
        out[k] = [placement.homogeneous for placement in data.oMi]
    return out


def attached(joints: np.ndarray, joint: int, placement: pin.SE3) -> np.ndarray:
    """World placements (N, 4, 4) of something fixed at ``placement`` in joint ``joint``'s
    frame, from the joints' placements (N, njoints, 4, 4) of :func:`joint_placements`."""
    return joints[:, joint] @ placement.homogeneous


def geometry_placements(joints: np.ndarray, visual_model: pin.GeometryModel) -> np.ndarray:
    """World placements (N, n_geometries, 4, 4) of the visual geometries, from the joints'
    placements (N, njoints, 4, 4)."""
    items = visual_model.geometryObjects
    return np.stack([attached(joints, g.parentJoint, g.placement) for g in items], axis=1)


def base_placements(state: BaseState | None) -> np.ndarray | None:
    """The base's placements (N, 4, 4) in the level axes: the model's moving axes and origin
    (:class:`~feeder.chain.results.BaseState` ``rotation``, ``position`` [m]); None for a base at
    rest."""
    if state is None:
        return None
    return np.array([homogeneous(*rp) for rp in zip(state.rotation, state.position, strict=True)])


def geometry_sphere(geometry_object: pin.GeometryObject) -> tuple[np.ndarray, float]:
    """A sphere that contains the geometry: its centre (3,) in the geometry's frame and its
    radius [m] (a mesh's bounding box, whose vertices need not surround the frame's origin: CAD
    exports often keep the assembly's origin)."""
    shape = geometry_object.geometry
    if hasattr(shape, "halfSide"):
        return np.zeros(3), float(np.linalg.norm(shape.halfSide))
    if hasattr(shape, "halfLength"):
        return np.zeros(3), float(math.hypot(shape.radius, shape.halfLength))
    if hasattr(shape, "radius"):
        return np.zeros(3), float(shape.radius)
    shape.computeLocalAABB()
    box = shape.aabb_local
    low, high = (np.asarray(x) * geometry_object.meshScale for x in (box.min_, box.max_))
    return (low + high) / 2.0, float(np.linalg.norm(high - low) / 2.0)


def sphere_centres(placements: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Model-frame centres (N, n, 3) [m] of the geometries' spheres (:func:`geometry_sphere`),
    from their placements (N, n, 4, 4) and local centres (n, 3)."""
    local = np.concatenate([centres, np.ones((len(centres), 1))], axis=1)
    return np.einsum("knij,nj->kni", placements, local)[..., :3]


def bounds(points: np.ndarray, reach: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest corners (3,) [m] of the box around the spheres: centres (..., n, 3),
    radii (n,) [m]."""
    low = (points - reach[:, None]).reshape(-1, 3).min(axis=0)
    high = (points + reach[:, None]).reshape(-1, 3).max(axis=0)
    return low, high


def extent_of(points: np.ndarray, reach: np.ndarray) -> float:
    """Largest side [m] of the box around the spheres (centres (..., n, 3), radii (n,))."""
    low, high = bounds(points, reach)
    return float((high - low).max())


def in_level_axes(points: np.ndarray, base: np.ndarray | None) -> np.ndarray:
    """Points (S, n, 3) [m] in the model's moving axes at S samples, in the level axes
    (S · n, 3): placed by the base's placements (S, 4, 4) at those samples (None: at rest)."""
    if base is not None:
        points = np.einsum("sij,snj->sni", base[:, :3, :3], points) + base[:, None, :3, 3]
    return points.reshape(-1, 3)
