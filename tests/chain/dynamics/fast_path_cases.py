"""Tracked motions of the mechanisms on which the fast paths of the load solve and of the
indeterminacy are compared with the singular value decompositions they replace (issue 29):
the feeding device, the examples (four-bar, Andrews' squeezer, Bricard's linkage), the
N-four-bar at N = 2, 10, 40 and the shared CAD exports."""

from __future__ import annotations

import importlib.util
import math
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

from feeder.chain import ClosedChain, track
from feeder.study.analyze import mount_mechanism

from ...conftest import REPO

EXAMPLES = REPO / "examples"
SHARED = REPO.parent / "shared" / "mechanisms"
SAMPLES = 12
"""Samples per motion: enough poses for a subsample to vary, few enough for a test."""

NAMES = (
    "device",
    "four_bar",
    "squeezer",
    "bricard",
    "n_four_bar_2",
    "n_four_bar_10",
    "n_four_bar_40",
    "cad_5bar_linkage",
    "cad_battobot_6d",
    "cad_cassie_like",
    "cad_robot_delta",
)


def _spec_path(name: str, folder: Path) -> Path:
    if name == "four_bar":
        return EXAMPLES / "four_bar" / "closures.toml"
    if name == "squeezer":
        return EXAMPLES / "andrews_squeezer" / "squeezer.toml"
    if name == "bricard":
        return EXAMPLES / "bricard" / "bricard.toml"
    if name.startswith("n_four_bar_"):
        script = EXAMPLES / "iftomm" / "n_four_bar.py"
        loaded = importlib.util.spec_from_file_location("n_four_bar", script)
        module = importlib.util.module_from_spec(loaded)
        loaded.loader.exec_module(module)
        return module.write(int(name.rsplit("_", 1)[1]), folder)[1]
    cad = name.removeprefix("cad_")
    shared = SHARED / cad / "robot.yaml"
    return shared if shared.exists() else EXAMPLES / "cad" / cad / "robot.yaml"


def motion_case(name: str, folder: Path):
    """(chain, actuated joints, q, v, a) of :data:`SAMPLES` samples: the device's cycle, or the
    mechanism's independent joints on ±0.05 rad sinusoids about their mounted pose (kept 0.1
    inside their limits), tracked."""
    if name == "device":
        from feeder import feeding_cycle, load_feeder
        from feeder.device import CLOSURE

        feeder = load_feeder("projectile")
        cycle = feeding_cycle(feeder, math.radians(-4.0))
        pick = np.linspace(0, cycle.t.size - 1, SAMPLES).round().astype(int)
        q, v, a = (feeder.to_pinocchio(x[pick]) for x in (cycle.q, cycle.v, cycle.a))
        return (
            ClosedChain(pin.Model(feeder.model), [CLOSURE]),
            ["piston_joint", "forearm_joint"],
            q,
            v,
            a,
        )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the CAD exports' plausibility warnings
        spec, chain, partition, _, q0 = mount_mechanism(_spec_path(name, folder), None, None)
    model = chain.model
    index = [model.joints[model.getJointId(j)].idx_q for j in spec.independent]
    low, high = model.lowerPositionLimit[index], model.upperPositionLimit[index]
    x0 = partition.independent_values(q0)
    room = np.isfinite(low) & np.isfinite(high) & (high - low > 0.3)
    x0 = np.where(room, np.clip(x0, low + 0.1, high - 0.1), x0)
    t = np.linspace(0.0, 1.0, SAMPLES)[:, None]
    w, ones = 2.0 * math.pi, np.ones(len(spec.independent))
    run = track(
        partition,
        q0,
        x0 + 0.05 * np.sin(w * t) * ones,
        0.05 * w * np.cos(w * t) * ones,
        -0.05 * w**2 * np.sin(w * t) * ones,
    )
    actuated = list(spec.actuated) or list(spec.independent)
    return chain, actuated, run.q, run.v, run.a
