"""The scene's MeshCat nodes and the render order of what is drawn over the bodies.

The scene lives under :data:`ROOT` in the model's own coordinates standing level (the level
axes); whatever rides on the base — the bodies, the arrows, the overlays, the hull — lives under
:data:`BASE`, whose transform is the base's placement in the level axes (:mod:`feeder.viz.scene`).
"""

from __future__ import annotations

ROOT = "feeder"
"""The scene's MeshCat node: the level axes."""
BASE = f"{ROOT}/base"
"""The node of whatever rides on the base (bodies, arrows, lines; the model's axes): its
transform is the base's placement in the level axes (identity on a base at rest)."""
ANIMATION = "animation"
"""The animation's own node, created last (:func:`feeder.viz.scene.draw_scene`)."""
ON_TOP = 10
"""Render order of arrows and lines: after the bodies, over them."""
