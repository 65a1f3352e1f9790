"""The viewer's one HTML page, for the device and for any mechanism alike: MeshCat's, with two
panels over the scene — a legend for every colour of the scene and a player (play/pause, loop,
a time slider with the time and the stage) — and, for the static page, :data:`PAGE_MARKER`.

MeshCat's own control panel ("Open Controls", top right) has play, pause, reset and a time
scrubber deep in its Animations folder, and no loop switch; the player puts them in view and
adds the loop. The panels are plain HTML and JavaScript that drive MeshCat's animator (the
page's global ``viewer.animator``), inserted before ``</body>`` of both the static page and the
live one (:func:`with_panels`).
The page's address may carry ``#t=2.5`` (open paused at that time [s]) and ``#loop`` (start
with looping on), e.g. to share one moment of the cycle.

MeshCat's static page applies its commands in whatever order their ``fetch`` calls complete;
:func:`static_page` applies them in the scene's order instead, synchronously, so that the page
is complete (the animation last) when the player starts.
"""

from __future__ import annotations

import html
import json
import math
import re

from .legend import DrawnScene

PAGE_MARKER = '<meta name="generator" content="feeder view">'
"""In the head of every static page of the viewer: the pages it may replace."""

_STYLE = """
#feeder-legend, #feeder-player {
  position: fixed; z-index: 10; background: rgba(255, 255, 255, 0.88); color: #222;
  font: 13px/1.45 sans-serif; border-radius: 6px; box-shadow: 0 1px 4px rgba(0, 0, 0, 0.3);
}
#feeder-legend { left: 10px; bottom: 58px; padding: 6px 9px; max-width: 300px;
  font-size: 12px; line-height: 1.35; }
#feeder-legend summary { font-weight: bold; cursor: pointer; }
#feeder-legend .mark { display: inline-block; width: 22px; margin-right: 7px;
  vertical-align: middle; }
#feeder-legend .body { height: 12px; border-radius: 2px; }
#feeder-legend .line { height: 3px; }
#feeder-legend .arrow { height: 4px; position: relative; }
#feeder-legend .arrow::after { content: ""; position: absolute; right: -6px; top: -4px;
  border-left: 8px solid var(--c); border-top: 6px solid transparent;
  border-bottom: 6px solid transparent; }
#feeder-player { left: 50%; bottom: 12px; transform: translateX(-50%); padding: 6px 10px;
  display: flex; align-items: center; gap: 10px; white-space: nowrap; }
#feeder-player button { min-width: 58px; }
#feeder-time { width: 34vw; }
"""

_SCRIPT = """
(function () {
  "use strict";
  var config = %(config)s;
  var animator = viewer.animator;
  var play = document.getElementById("feeder-play");
  var loop = document.getElementById("feeder-loop");
  var slider = document.getElementById("feeder-time");
  var clock = document.getElementById("feeder-clock");
  var stage = document.getElementById("feeder-stage");
  var LOOP_REPEAT = 2201;  // THREE.LoopRepeat
  var options = new URLSearchParams(location.hash.slice(1));
  var pending = options.has("t") ? (parseFloat(options.get("t")) - config.start) * config.slow
    : null;
  var loaded = null;  // the animation's actions the controls were last set up for
  loop.checked = options.has("loop");

  function applyLoop() {
    animator.actions.forEach(function (action) {
      action.setLoop(LOOP_REPEAT, loop.checked ? Infinity : 1);
    });
  }
  function seek(t) {
    if (animator.playing) { animator.pause(); }
    animator.seek(t);
    animator.display_progress(t);
  }
  play.addEventListener("click", function () {
    if (!animator.actions.length) { return; }
    if (animator.playing) { animator.pause(); return; }
    applyLoop();
    if (animator.time >= animator.duration - 1e-9) { animator.reset(); }
    animator.play();
  });
  loop.addEventListener("change", applyLoop);
  slider.addEventListener("input", function () { seek(parseFloat(slider.value)); });

  function refresh() {
    if (animator.actions.length) {
      if (loaded !== animator.actions) {  // a (new) animation arrived
        loaded = animator.actions;
        applyLoop();
        if (pending !== null && isFinite(pending)) { seek(pending); }
        pending = null;
      }
      var played = Math.min(animator.time, animator.duration);
      var t = config.start + played / config.slow;  // the motion's time [s]
      slider.max = animator.duration;
      slider.value = played;
      clock.textContent = "t = " + t.toFixed(config.digits) + " s";
      if (config.stages.length) {
        var k = 0;
        while (k < config.stages.length - 1 && t >= config.boundaries[k + 1]) { k += 1; }
        stage.textContent = "stage " + (k + 1) + ": " + config.stages[k];
      }
      play.textContent = animator.playing ? "pause" : "play";
    }
    requestAnimationFrame(refresh);
  }
  refresh();
})();
"""


def panels_html(drawn: DrawnScene, title: str) -> str:
    """The legend and the player for a drawn scene, as HTML to insert before ``</body>``."""
    rows = [f"<summary>{html.escape(title)}</summary>"]
    for entry in drawn.legend:
        if entry.mark == "note":
            rows.append(f"<div>{html.escape(entry.label)}</div>")
            continue
        rows.append(
            f'<div><span class="mark {entry.mark}" style="background: {entry.color}; '
            f'--c: {entry.color}"></span>{html.escape(entry.label)}</div>'
        )
    length = drawn.arrow_length
    if drawn.newtons_per_metre > 0.0:
        rows.append(
            f"<div>force arrows to one scale: {length:.3g} m long = "
            f"{drawn.newtons_per_metre * length:.4g} N, from the point the force acts on</div>"
        )
    if drawn.moment_scale > 0.0:
        rows.append(
            f"<div>moment arrows to one scale: {length:.3g} m long = "
            f"{drawn.moment_scale * length:.4g} N·m, along the moment's axis</div>"
        )
    if drawn.slow_motion > 1.0:
        rows.append(f"<div>played {drawn.slow_motion:.3g}× slower than the motion</div>")
    rows.append(f"<div>{html.escape(drawn.axes)}</div>")
    start, end = drawn.boundaries[0], drawn.boundaries[-1]
    duration = end - start
    config = json.dumps(
        {
            "start": start,
            "slow": drawn.slow_motion,
            "boundaries": list(drawn.boundaries),
            "stages": list(drawn.stages),
            "digits": max(3, 3 - math.floor(math.log10(duration))) if duration > 0.0 else 3,
        }
    )
    if duration <= 0.0:  # a pose: nothing to play
        player = [f'<div id="feeder-player">pose at t = {start:g} s (no motion)</div>']
    else:
        player = [
            '<div id="feeder-player">',
            '<button id="feeder-play" type="button">play</button>',
            '<label><input id="feeder-loop" type="checkbox"> loop</label>',
            f'<input id="feeder-time" type="range" min="0" max="{duration * drawn.slow_motion}" '
            'step="0.001" value="0" aria-label="time">',
            f'<span id="feeder-clock">t = {start:.3f} s</span>',
            '<span id="feeder-stage"></span>',
            "</div>",
            f"<script>{_SCRIPT % {'config': config}}</script>",
        ]
    return "\n".join(
        [
            f"<style>{_STYLE}</style>",
            '<details id="feeder-legend" open>',
            *rows,
            "</details>",
            *player,
        ]
    )


_FETCHED_COMMAND = re.compile(
    r'fetch\("(data:application/octet-binary;base64,[A-Za-z0-9+/=]*)"\)\s*'
    r"\.then\(res => res\.arrayBuffer\(\)\)\s*"
    r"\.then\(buffer => viewer\.handle_command_bytearray\(new Uint8Array\(buffer\)\)\);"
)

_IN_ORDER = """
(function () {
  %s.forEach(function (url) {
    var text = atob(url.slice(url.indexOf(",") + 1)), bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i += 1) { bytes[i] = text.charCodeAt(i); }
    viewer.handle_command_bytearray(bytes);
  });
})();
"""


def static_page(page: str, panels: str) -> str:
    """MeshCat's static page with its commands applied in order, ``panels`` inserted and
    :data:`PAGE_MARKER` in its head."""
    commands = _FETCHED_COMMAND.findall(page)
    ordered = iter([_IN_ORDER % json.dumps(commands)])  # where the first command was
    page = with_panels(_FETCHED_COMMAND.sub(lambda _: next(ordered, ""), page), panels)
    return page.replace("<head>", f"<head>{PAGE_MARKER}", 1)


def with_panels(page: str, panels: str) -> str:
    """``page`` (MeshCat's HTML) with ``panels`` inserted before its last ``</body>``."""
    head, body_end, tail = page.rpartition("</body>")
    return f"{head}{panels}\n{body_end}{tail}"
