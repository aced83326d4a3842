"""The package's types as a user's type checker sees them (issue 35: stubs, py.typed, Literal
choices): mypy --strict passes a correct script and reports each marked mistake in another, on its
line. Run by CTest (test `python_typing`) against the package in this build tree."""

import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent / "typed_usage"


def mypy(script):
    env = dict(os.environ, MYPYPATH=os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", os.devnull,
                           str(HERE / script)], capture_output=True, text=True, env=env, timeout=600)


def test_a_correct_script_type_checks_strictly():
    result = mypy("user_script.py")
    assert result.returncode == 0, result.stdout + result.stderr


def test_each_mistake_is_reported_on_its_line():
    result = mypy("user_mistakes.py")
    lines = (HERE / "user_mistakes.py").read_text().splitlines()
    marked = {i + 1 for i, line in enumerate(lines) if "# MISTAKE" in line}
    reported = {int(line.split(":")[1]) for line in result.stdout.splitlines() if line.startswith(str(HERE))
                and ": error:" in line}
    assert result.returncode == 1
    assert reported == marked, result.stdout


def test_a_kubelka_munk_script_type_checks_and_its_mistakes_are_reported_on_their_lines():
    correct = mypy("kubelka_munk_script.py")
    assert correct.returncode == 0, correct.stdout + correct.stderr
    result = mypy("kubelka_munk_mistakes.py")
    lines = (HERE / "kubelka_munk_mistakes.py").read_text().splitlines()
    marked = {i + 1 for i, line in enumerate(lines) if "# MISTAKE" in line}
    reported = {int(line.split(":")[1]) for line in result.stdout.splitlines() if line.startswith(str(HERE))
                and ": error:" in line}
    assert result.returncode == 1
    assert reported == marked, result.stdout
