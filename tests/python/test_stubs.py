"""The type stub lists exactly what the extension module exports."""

import ast
import inspect
import os

import sinew._core as core

STUB = os.path.join(os.path.dirname(core.__file__), "_core.pyi")


def stub_members():
    tree = ast.parse(open(STUB).read())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef) and n.name != "__init__"}
    return out


def test_stub_matches_runtime():
    stubs = stub_members()
    runtime = {n for n, v in vars(core).items() if inspect.isclass(v)}
    assert set(stubs) == runtime
    for cls in ("Model", "Sim"):
        public = {n for n in dir(getattr(core, cls)) if not n.startswith("_")}
        assert stubs[cls] == public, (cls, stubs[cls] ^ public)
