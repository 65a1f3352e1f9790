"""Analysis of a user's closed-chain mechanism (``feeder analyze``): its mobility, its motion
followed on one assembly branch, and the loads and reactions of every joint and cut.

Data flow: side-file and model (:mod:`feeder.chain.readers`) → :class:`~feeder.chain.ClosedChain`
→ mobility report at the first sample (:mod:`feeder.chain.mobility`) → the motion table's
independent coordinates tracked by continuation (:meth:`~feeder.chain.Partition.track`) →
inverse dynamics with every reaction (:mod:`feeder.chain.dynamics.inverse`) → the table
(:meth:`Analysis.columns`) and its summary.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..chain.assembly.partition import Partition
from ..chain.dynamics.inverse import ChainDynamics, ChainLoads, inverse_dynamics
from ..chain.mobility import MobilityReport, mobility
from ..chain.model.closure import ClosedChain
from ..chain.readers.mechanism import load_mechanism, read_spec
from ..chain.readers.motion_table import MotionTable, read_motion
from ..chain.readers.spec import MechanismSpec


@dataclass(frozen=True)
class Analysis:
    """A mechanism's motion and loads, N samples.

    Attributes:
        spec: The side-file's content.
        chain: The closed chain.
        motion: The prescribed motion of the independent joints.
        q, v, a: The whole chain's motion, (N, nq), (N, nv), (N, nv).
        gain: Velocity gain at every sample, (N,) (distance to a singular pose).
        loads: Actuator loads, closure forces and every joint's reaction.
        report: Mobility at the first sample.
    """

    spec: MechanismSpec
    chain: ClosedChain
    motion: MotionTable
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    gain: np.ndarray
    loads: ChainLoads
    report: MobilityReport

    def columns(self) -> dict[str, np.ndarray]:
        """The loads table, each column (N,), SI units, world axes:

        ``t``; ``q_<joint>``, ``v_<joint>``, ``a_<joint>`` of every joint (rad or m and rates);
        ``velocity_gain``; ``tau_<joint>`` of the actuated joints (N or N·m along the joint
        axis); ``<closure>_force_x|y|z`` and ``<closure>_moment_x|y|z`` (the cut's wrench on the
        body of its first frame, moment about that frame's origin); ``<joint>_force_x|y|z`` and
        ``<joint>_moment_x|y|z`` (the wrench the parent exerts on the child, about the joint's
        origin) and their magnitudes ``<joint>_force``, ``<joint>_moment``.
        """
        model = self.chain.model
        cols: dict[str, np.ndarray] = {"t": self.motion.t}
        for j in range(1, model.njoints):
            joint = model.joints[j]
            if joint.nq == joint.nv == 1:
                name = model.names[j]
                cols[f"q_{name}"] = self.q[:, joint.idx_q]
                cols[f"v_{name}"] = self.v[:, joint.idx_v]
                cols[f"a_{name}"] = self.a[:, joint.idx_v]
        cols["velocity_gain"] = self.gain
        for name, values in self.loads.actuators.items():
            cols[f"tau_{name}"] = values
        for label, wrench in self.loads.closures.items():
            for what, vector in (("force", wrench.force), ("moment", wrench.moment)):
                for k, axis in enumerate("xyz"):
                    cols[f"{label}_{what}_{axis}"] = vector[:, k]
        for name, wrench in self.loads.joints.items():
            for what, vector in (("force", wrench.force), ("moment", wrench.moment)):
                cols[f"{name}_{what}"] = np.linalg.norm(vector, axis=1)
                for k, axis in enumerate("xyz"):
                    cols[f"{name}_{what}_{axis}"] = vector[:, k]
        return cols

    def summary(self) -> str:
        """The mobility report, peaks of the loads and the indeterminacy convention, as text."""
        t = self.motion.t
        lines = [self.report.text(), f"motion: {t.size} samples over {t[-1] - t[0]:.4g} s"]
        if self.motion.differentiated:
            lines.append(
                "  rates differentiated from positions for: "
                + ", ".join(self.motion.differentiated)
            )
        k = int(np.argmax(self.gain))
        lines.append(f"  largest velocity gain {self.gain[k]:.3g} at t = {t[k]:.4g} s")
        for name, values in self.loads.actuators.items():
            k = int(np.argmax(np.abs(values)))
            unit = "N" if self._prismatic(name) else "N·m"
            lines.append(
                f"  peak actuator load {name}: max |τ| = {abs(values[k]):.4g} {unit} "
                f"(sign {'+' if values[k] >= 0 else '−'}) at t = {t[k]:.4g} s"
            )
        for name, wrench in self.loads.joints.items():
            force = np.linalg.norm(wrench.force, axis=1)
            k = int(np.argmax(force))
            lines.append(f"  peak reaction force in {name}: {force[k]:.4g} N at t = {t[k]:.4g} s")
        if self.loads.indeterminate:
            lines.append(
                "  statically indeterminate closure rows: "
                + ", ".join(self.loads.indeterminate)
                + f" ({self.loads.convention})"
            )
        return "\n".join(lines)

    def _prismatic(self, joint: str) -> bool:
        model = self.chain.model
        return model.joints[model.getJointId(joint)].shortname().startswith("JointModelP")


def check_mechanism(spec_path: str | Path, model: str | Path | None = None) -> str:
    """The mobility report of a mechanism at its model's reference pose (``feeder analyze
    --check``), assembled with the side-file's independent joints from the neutral pose."""
    spec = read_spec(spec_path, model)
    chain = load_mechanism(spec)
    partition = Partition(chain, spec.independent)
    q = partition.assemble(pin.neutral(chain.model))
    return mobility(chain, q, spec.independent).text()


def analyze(
    spec_path: str | Path,
    motion_path: str | Path,
    model: str | Path | None = None,
    q_guess: np.ndarray | None = None,
) -> Analysis:
    """Follow the motion table on one branch and compute every load and reaction.

    Args:
        spec_path: The closure side-file (TOML, :mod:`feeder.chain.readers.side_file`).
        motion_path: The motion table (CSV).
        model: The model file, overriding the side-file's.
        q_guess: A configuration that picks the assembly branch (default: the model's neutral).

    Raises:
        FeederError: Bad files, an unreachable or singular pose, a motion the actuated joints
            cannot produce (each with its own message).
    """
    spec = read_spec(spec_path, model)
    chain = load_mechanism(spec)
    table = read_motion(motion_path, spec.independent)
    partition = Partition(chain, spec.independent)
    guess = pin.neutral(chain.model) if q_guess is None else chain.check_q(q_guess)
    q, v, a, gain = partition.track(guess, table.x, table.dx, table.ddx)
    dyn = ChainDynamics(chain, spec.actuated, spec.stiffness)
    loads = inverse_dynamics(dyn, q, v, a)
    report = mobility(chain, q[0], spec.independent)
    return Analysis(spec, chain, table, q, v, a, gain, loads, report)
