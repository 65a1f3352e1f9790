"""The README's promises: its test command is the one CI runs, every command in it is spelled
for the quick start's virtual environment and parses, its Python examples run, and — in a fresh
copy of the repository with a fresh virtual environment — every command runs as written.

The last check installs the package from scratch (about a minute and a half) and runs every
command (another minute): too slow for the default run, it runs when ``FEEDER_README_COMMANDS``
is set, as its own step of ``.ci/run``.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import signal
import subprocess

import pytest

from feeder.study.csv import read_csv

from .conftest import REPO

README = (REPO / "README.md").read_text(encoding="utf-8")
INSTALL_TIMEOUT = 900.0
"""[s] The quick start's first command: a fresh virtual environment, the package and its
dependencies from the package index (~90 s here), and a cycle at 1 kHz."""
COMMAND_TIMEOUT = 300.0
"""[s] Any other README command (the slowest, a cycle with its figures, takes ~10 s)."""
VIEWER_WAIT = 120.0
"""[s] Longest wait for ``feeder view`` to print its address."""
ROWS = 4001
"""The quick start's cycle: 4 s at 1 kHz, both ends included (REFERENCE.md)."""


def bash_blocks(text: str = README) -> list[list[str]]:
    """The commands of each ```bash block of ``text``: its lines, comments stripped."""
    blocks = re.findall(r"```bash\n(.*?)```", text, flags=re.S)
    return [
        [line.split("  #")[0].strip() for line in block.splitlines() if line and line[0] != "#"]
        for block in blocks
    ]


def quick_start_commands() -> list[str]:
    section = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    return [command for block in bash_blocks(section) for command in block]


def later_commands() -> list[str]:
    """Every command after the quick start: the bash blocks' lines and the ``.venv/bin/...``
    commands quoted in the text."""
    text = README.split("## Quick start", 1)[1].split("\n## ", 1)[1]
    commands = [command for block in bash_blocks(text) for command in block]
    prose = re.sub(r"```.*?```", "", text, flags=re.S)
    quoted = re.findall(r"`(\.venv/bin/[^`]+)`", prose)
    return list(dict.fromkeys(commands + quoted))


def python_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README, flags=re.S)


def test_exactly_two_quick_start_commands_and_ci_runs_the_test_one():
    commands = quick_start_commands()
    assert len(commands) == 2
    assert "pytest" in commands[1]
    assert commands[1] in (REPO / ".ci" / "run").read_text(encoding="utf-8")


def test_main_study_command_names_existing_subcommand():
    from feeder.cli import parser

    words = shlex.split(quick_start_commands()[0].split("&&")[-1])
    assert words[0] == ".venv/bin/feeder"
    args = parser().parse_args(words[1:])
    assert args.elevation == -4.0


def test_every_command_uses_the_quick_starts_environment():
    """The quick start never activates .venv: a bare ``feeder`` or ``python`` would be another
    program, or none (``python benchmarks/bench_cycle.py`` failed with ModuleNotFoundError)."""
    commands = later_commands()
    assert len(commands) >= 10
    for command in commands:
        assert command.startswith((".venv/bin/feeder ", ".venv/bin/python ")), command
    spans = re.findall(
        r"`((?:feeder|python3?|pip) [^`]*)`", re.sub(r"```.*?```", "", README, flags=re.S)
    )
    assert not spans, f"commands without .venv/bin/: {spans}"


def test_every_feeder_command_parses():
    from feeder.cli import parser

    for command in later_commands():
        words = shlex.split(command)
        if words[0] == ".venv/bin/feeder":
            parser().parse_args(words[1:])  # argparse exits on a misspelt option


@pytest.mark.parametrize("index", range(len(python_blocks())))
def test_python_examples_run(monkeypatch, index):
    monkeypatch.chdir(REPO)  # the examples name files relative to the repository
    exec(compile(python_blocks()[index], "README.md", "exec"), {})


def copy_of_the_repository(target):
    """The files a commit would hold (tracked, and new files not ignored) copied to ``target``."""
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
        cwd=REPO,
        capture_output=True,
        check=True,
    ).stdout.decode("utf-8")
    for name in filter(None, listed.split("\0")):
        source = REPO / name
        if source.is_file():
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)


def run(command: str, cwd, timeout: float) -> subprocess.CompletedProcess:
    done = subprocess.run(
        ["bash", "-c", command], cwd=cwd, capture_output=True, text=True, timeout=timeout
    )
    assert done.returncode == 0, f"{command}\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


def serve_and_stop(command: str, cwd) -> None:
    """A command that serves until Ctrl-C: wait for its address and its "press Ctrl-C" line,
    then send SIGINT, as a user would."""
    server = subprocess.Popen(
        shlex.split(command),
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        address, prompt = server.stdout.readline(), server.stdout.readline()
        assert "open http://127.0.0.1:" in address, address + server.stderr.read()
        assert "press Ctrl-C" in prompt, prompt
    finally:
        server.send_signal(signal.SIGINT)
        server.communicate(timeout=VIEWER_WAIT)
    assert server.returncode == 0


@pytest.mark.skipif(
    not os.environ.get("FEEDER_README_COMMANDS"),
    reason="slow (a fresh virtual environment): .ci/run runs it with FEEDER_README_COMMANDS=1",
)
def test_readme_commands_run_as_written_in_a_fresh_environment(tmp_path):
    copy_of_the_repository(tmp_path)
    assert not (tmp_path / ".venv").exists()
    run(quick_start_commands()[0], tmp_path, INSTALL_TIMEOUT)
    table = read_csv(tmp_path / "results" / "cycle.csv")
    assert len(table["t"]) == ROWS
    manifest = json.loads((tmp_path / "results" / "feeder-run.json").read_text("utf-8"))
    assert manifest["complete"] and manifest["command"].startswith("feeder cycle --elevation -4")
    for command in later_commands():
        if command.startswith(".venv/bin/feeder view") and "--html" not in command:
            serve_and_stop(command, tmp_path)
        else:
            run(command, tmp_path, COMMAND_TIMEOUT)
    for block in python_blocks():
        run(f".venv/bin/python - <<'EOF'\n{block}EOF", tmp_path, COMMAND_TIMEOUT)
    assert (tmp_path / "cycle.html").stat().st_size > 500_000
    assert (tmp_path / "my_results" / "feeder-run.json").is_file()
