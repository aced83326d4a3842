"""`python -m metamer ARGS` (and the `metamer` console script): the command-line tool installed with
the package, metamer/bin/metamer, run with ARGS in this process's place (docs/cli.md)."""

import os
import sys


def main():
    tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "metamer")
    if not os.access(tool, os.X_OK):
        sys.exit(f"metamer: the command-line tool is missing from the package ({tool}): reinstall metamer")
    sys.stdout.flush()
    os.execv(tool, ["metamer", *sys.argv[1:]])


if __name__ == "__main__":
    main()
