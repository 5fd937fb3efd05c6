"""The type stubs say what the native module has: every class, function and member."""

import ast
from pathlib import Path

import carfollow._carfollow as native

STUB = Path(native.__file__).parent / "_carfollow.pyi"
TYPING_ONLY = {"Tracker", "Controller"}


def stub_names():
    tree = ast.parse(STUB.read_text())
    names = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names[node.name] = {
                n.name
                for n in node.body
                if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")
            }
        elif isinstance(node, ast.FunctionDef):
            names[node.name] = None
    return names


def test_every_stubbed_name_exists_and_every_public_one_is_stubbed():
    stubbed = stub_names()
    for name, members in stubbed.items():
        if name in TYPING_ONLY:
            continue
        assert hasattr(native, name), name
        if members is not None:
            cls = getattr(native, name)
            public = {m for m in dir(cls) if not m.startswith("_")}
            assert members == public, (name, members ^ public)
    public = {n for n in dir(native) if not n.startswith("_")}
    assert public <= set(stubbed), public - set(stubbed)
