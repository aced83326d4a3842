"""`python -m metamer ARGS` (and the `metamer` console script): the command-line tool installed with
the package, metamer/bin/metamer, run with ARGS in this process's place (docs/cli.md); and
`metamer camera-report …`, the camera report (metamer/report.py, docs/camera.md), which is Python's."""

import os
import sys


def main():
    # The camera report is Python's (matplotlib): the one command not in the C++ tool.
    if sys.argv[1:2] == ["camera-report"]:
        from .report import main as report
        report(sys.argv[2:])
        return
    tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "metamer")
    if not os.access(tool, os.X_OK):
        sys.exit(f"metamer: the command-line tool is missing from the package ({tool}): reinstall metamer")
    sys.stdout.flush()
    os.execv(tool, ["metamer", *sys.argv[1:]])


if __name__ == "__main__":
    main()
