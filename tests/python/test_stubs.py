"""The type stubs (ispars/__init__.pyi) against the module: every public class, function, method
and property of one is declared in the other (constructors aside), so editors and mypy see what is there."""
import ast
import pathlib

import ispars

STUBS = pathlib.Path(ispars.__file__).with_name("__init__.pyi")
TYPED_DICTS = {"Tour", "Batch"}  # the stubs' names for the dicts the module returns


def declared():
    tree = ast.parse(STUBS.read_text())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | {
                n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.FunctionDef):
            out[node.name] = None
        elif isinstance(node, ast.AnnAssign) and node.target.id in ("__version__", "HAS_CLIENT"):
            out[node.target.id] = None
    return out


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_every_public_name_is_in_the_stubs_and_every_stub_in_the_module():
    stubs = declared()
    exported = set(ispars.__all__)
    assert exported == set(stubs) - TYPED_DICTS
    for name in exported:
        obj = getattr(ispars, name)
        if not isinstance(obj, type) or issubclass(obj, Exception):
            continue
        members = public(obj) | {n for n in ("__iter__", "__next__", "__enter__", "__exit__") if hasattr(obj, n)}
        assert members == stubs[name] - {"__init__"}, f"{name}: module only {members - stubs[name]}, stubs only {stubs[name] - members - {'__init__'}}"


def test_every_public_callable_has_a_docstring():
    for name in ispars.__all__:
        obj = getattr(ispars, name)
        assert obj.__doc__, name
        if isinstance(obj, type) and not issubclass(obj, Exception):
            for member in public(obj):
                assert getattr(obj, member).__doc__ or isinstance(getattr(obj, member), property), f"{name}.{member}"
