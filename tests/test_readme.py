"""The README's promises: its test command is the one CI runs, and its API example runs."""

from __future__ import annotations

import re

from .conftest import REPO

README = (REPO / "README.md").read_text(encoding="utf-8")


def quick_start_commands() -> list[str]:
    section = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```bash\n(.*?)```", section, flags=re.S)
    return [line for block in blocks for line in block.splitlines() if line and line[0] != "#"]


def test_exactly_two_quick_start_commands_and_ci_runs_the_test_one():
    commands = quick_start_commands()
    assert len(commands) == 2
    assert "pytest" in commands[1]
    assert commands[1] in (REPO / ".ci" / "run").read_text(encoding="utf-8")


def test_main_study_command_names_existing_subcommand():
    from feeder.__main__ import _parser

    words = quick_start_commands()[0].split("&&")[-1].split()
    args = _parser().parse_args(words[1:])
    assert args.elevation == -4.0


def test_api_example_runs():
    block = re.search(r"## Python API\n+```python\n(.*?)```", README, flags=re.S).group(1)
    exec(compile(block, "README.md", "exec"), {})
