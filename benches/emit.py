"""Prints a bench's Markdown table and writes it to `out` when given."""


def emit(text, out=None):
    print(text)
    if out:
        with open(out, "w") as f:
            f.write(text)
