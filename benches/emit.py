"""Prints a bench's Markdown table and writes it to `out` when given."""

import os
import sys


def emit(text, out=None):
    print(text)
    if out:
        with open(out, "w") as f:
            f.write(text)


def invocation() -> str:
    """The command that ran this bench, as the comment a results file starts with."""
    return f"<!-- {' '.join(['python', 'benches/' + os.path.basename(sys.argv[0])] + sys.argv[1:])} -->"
