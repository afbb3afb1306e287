"""The type stub `_bcifs.pyi` is the compiled module's: every public name of the module is in the
stub and every name of the stub in the module, and each function's and method's parameters (names,
kinds and literal defaults) are the ones the module reports in `__text_signature__` (issue 43 §6:
the stub was checked by nothing)."""

import ast
import inspect
import pathlib

import bcifs._bcifs as module

STUB = pathlib.Path(__file__).resolve().parents[1] / "bcifs" / "_bcifs.pyi"


def stub_definitions():
    """`{name: node}` of the stub's top level, and `{class: {name: node}}` of its classes."""
    tree = ast.parse(STUB.read_text())
    top, classes = {}, {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            top[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            top[node.target.id] = node
        if isinstance(node, ast.ClassDef):
            classes[node.name] = {
                n.name: n for n in node.body if isinstance(n, (ast.FunctionDef, ast.AnnAssign)) and hasattr(n, "name")
            }
            classes[node.name].update(
                {n.target.id: n for n in node.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}
            )
    return top, classes


def stub_parameters(node):
    """`[(name, kind, default)]` of a stub function, `self` left out."""
    a = node.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    for arg, default in zip(positional, defaults):
        out.append((arg.arg, "positional", literal(default)))
    if a.vararg:
        out.append((a.vararg.arg, "*", None))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, "keyword", literal(default)))
    if a.kwarg:
        out.append((a.kwarg.arg, "**", None))
    return [p for p in out if p[0] not in ("self", "cls")]


def literal(node):
    if node is None:
        return None
    try:
        return ast.literal_eval(node)
    except ValueError:
        return "..."


def module_parameters(function):
    """The same from the compiled function's `__text_signature__`."""
    text = function.__text_signature__
    for receiver in ("$self, /, ", "$cls, /, ", "$type, /, ", "$self, ", "$cls, ", "$self", "$cls"):
        text = text.replace(receiver, "")
    tree = ast.parse(f"def f{text}: pass").body[0]
    return stub_parameters(tree)


def key_default(key):
    """A key's default as the Python value its keyword takes (`"800x800"` is `(800, 800)`)."""
    text, kind = key["default"], key["kind"]
    if kind == "switch":
        return False
    if text is None:
        return None
    if kind == "size":
        return tuple(int(t) for t in text.split("x"))
    if kind == "angles":
        return tuple(float(t) for t in text.split(","))
    return {"count": int, "number": float}.get(kind, str)(text)


def spelled_options(keywords):
    """The keyword-only parameters a stub spells out for `**options`: every key of
    `option_keys()` in its order with its default, then Python's own `tone`."""
    keys = module.option_keys()
    expected = [(k["name"], "keyword", key_default(k)) for k in keys] + [("tone", "keyword", None)]
    return keywords == expected


def same(stub, compiled):
    """Equal parameters; a default the module shows as `...` (not a literal) may be any. A
    function taking `**options` (the library's keys) has them spelled out in the stub."""
    if compiled and compiled[-1][:2] == ("options", "**"):
        head = [p for p in stub if p[1] != "keyword"]
        return same_plain(head, compiled) and spelled_options([p for p in stub if p[1] == "keyword"])
    return same_plain(stub, compiled)


def same_plain(stub, compiled):
    return len(stub) == len(compiled) and all(
        s[:2] == c[:2] and (c[2] is Ellipsis or s[2] == c[2]) for s, c in zip(stub, compiled)
    )


def public(names):
    return {n for n in names if not n.startswith("__") and n not in ("add_note", "args", "with_traceback")}


def test_the_stub_names_what_the_module_has():
    top, classes = stub_definitions()
    assert public(dir(module)) == public(top), "module vs stub"
    for name, members in classes.items():
        cls = getattr(module, name)
        if issubclass(cls, Exception):
            continue
        assert public(dir(cls)) == public(members), name


def test_every_signature_is_the_module_s():
    top, classes = stub_definitions()
    checked = 0
    for name, node in top.items():
        obj = getattr(module, name)
        if inspect.isbuiltin(obj) and obj.__text_signature__:
            assert same(stub_parameters(node), module_parameters(obj)), (name, stub_parameters(node), module_parameters(obj))
            checked += 1
    for cls_name, members in classes.items():
        cls = getattr(module, cls_name)
        for name, node in members.items():
            # A constructor's signature is its class's.
            method = cls if name in ("__init__", "__new__") else getattr(cls, name)
            if isinstance(node, ast.FunctionDef) and getattr(method, "__text_signature__", None):
                assert same(stub_parameters(node), module_parameters(method)), (cls_name, name, stub_parameters(node))
                checked += 1
    assert checked > 25, checked
