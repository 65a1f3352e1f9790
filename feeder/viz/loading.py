"""The controlled run's error over the cycle and the hold (``loading_error.png``): how far the
payload is from where the cycle puts it, and from the rammer's line at the loading pose."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from .axes import STYLES, log_curves, panel_title
from .catalog import elevation_text
from .figures import finish, mark_stages


def loading_error_figure(
    run: Mapping[str, np.ndarray],
    boundaries: Sequence[float],
    elevation: float,
    base: str,
) -> Figure:
    """Two panels against time, log axes, the stages and the hold marked: the payload's
    position error and, over the hold, its distance from the rammer's line [mm] with the
    position tolerance;
    the payload axis's angle error and the arm's and forearm's |Δφ3|, |Δφ4| [mrad] with the
    angle tolerance.

    Args:
        run: ``t`` [s] (M,) over the cycle and the hold; ``payload_error``, ``off_line`` [m];
            ``axis_error``, ``phi3_error``, ``phi4_error`` [rad], (M,) each;
            ``position_tolerance`` [m] and ``angle_tolerance`` [rad], (1,) each.
        boundaries: Stage boundaries [s], (4,).
        elevation: ε [rad].
        base: The base's description, for the title.
    """
    t = run["t"]
    fig = Figure(figsize=(10.0, 7.6))
    top, bottom = fig.subplots(2, 1, sharex=True)
    end = boundaries[-1]
    hold, whole = t >= end, np.ones(t.size, dtype=bool)
    panels = (
        (
            top,
            [
                ("payload CG from its prescribed place", run["payload_error"] * 1e3, whole),
                ("payload CG from the rammer's line", run["off_line"] * 1e3, hold),
            ],
            "mm",
            "position error",
            float(run["position_tolerance"][0]) * 1e3,
        ),
        (
            bottom,
            [
                ("payload axis", run["axis_error"] * 1e3, whole),
                ("|Δφ3| arm", run["phi3_error"] * 1e3, whole),
                ("|Δφ4| forearm", run["phi4_error"] * 1e3, whole),
            ],
            "mrad",
            "angle error",
            float(run["angle_tolerance"][0]) * 1e3,
        ),
    )
    for ax, series, unit, quantity, tolerance in panels:
        kept = [(label, values[mask], mask) for label, values, mask in series]
        curves = log_curves([(label, values) for label, values, _ in kept], unit, tolerance)
        for k, (curve, (_, _, mask)) in enumerate(zip(curves, kept, strict=True)):
            style = STYLES[k % len(STYLES)]
            ax.semilogy(t[mask], curve.values, label=curve.label, color=f"C{k}", linestyle=style)
        ax.axhline(
            tolerance,
            color="k",
            linestyle=":",
            linewidth=1.0,
            label=f"tolerance {tolerance:g} {unit}",
        )
        mark_stages(ax, boundaries)
        ax.axvspan(end, t[-1], color="0.92", zorder=0)
        ax.text(0.5 * (end + t[-1]), 1.01, "hold", transform=ax.get_xaxis_transform(),
                ha="center", va="bottom", fontsize=7, color="0.3")  # fmt: skip
        ax.set_xlim(t[0], t[-1])
        ax.set_ylabel(f"{quantity} [{unit}]")
        ax.grid(True, which="major", linewidth=0.4, alpha=0.6)
        below = -0.2 if ax is bottom else -0.08  # clear of the time axis's label
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, below), ncol=2, fontsize=7)
    bottom.set_xlabel("time t [s]")
    fig.suptitle(f"Controlled run: loading error, {elevation_text(elevation)}", fontsize=11)
    panel_title(top, base, fontsize=8, pad=16)
    finish(fig, top=0.9, bottom=1.3, hspace=1.5)
    return fig
