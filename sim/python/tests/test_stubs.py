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


def words(doc):
    """A docstring's words, with reST's ``code`` and Markdown's `code` alike."""
    return " ".join((doc or "").replace("``", "`").split())


def test_every_stubbed_member_has_the_modules_docstring():
    """The book's Python API page is generated from the stubs: each public member's
    docstring there is the one the module itself carries (``help()`` shows it)."""
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            assert words(ast.get_docstring(node)) == words(getattr(native, node.name).__doc__), (
                node.name
            )
        if not isinstance(node, ast.ClassDef):
            continue
        assert ast.get_docstring(node), node.name
        for member in node.body:
            if not isinstance(member, ast.FunctionDef) or member.name.startswith("_"):
                continue
            stubbed = words(ast.get_docstring(member))
            assert stubbed, f"{node.name}.{member.name} has no docstring in the stub"
            if node.name in TYPING_ONLY:
                continue
            runtime = words(getattr(getattr(native, node.name), member.name).__doc__)
            assert stubbed == runtime, (f"{node.name}.{member.name}", stubbed, runtime)
