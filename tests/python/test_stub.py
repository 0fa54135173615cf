"""The type stub python/roadcross.pyi against the module it describes (ctest python.stub).

The stub is read with `ast`; the module is imported. pybind11 states what the binding really
accepts and returns: the first line of each function's __doc__ is its signature (parameter
names, types, a `*` before keyword-only parameters, defaults), and each property's getter's
__doc__ ends with its return type. The checks, each in both directions:
  - names: every public name of the module and every attribute/method a class defines (its own
    __dict__, dunders included) is in the stub with the same kind (class, function, property,
    method), and nothing else is;
  - signatures: parameter names, positional / keyword-only, defaults (the values), parameter and
    return types (pybind11's spelling mapped to typing's, see `type_matches`);
  - exception bases, and that `code` (declared on Error) is there on a raised error;
  - docstrings equal the binding's (whitespace-normalised, so that the stub can wrap them), and
    every property has one; Literal[...] values equal the quoted values of the docstring;
  - every name an annotation uses is imported or defined in the stub.
A second test mutates the stub (a renamed property, a dropped `*`, ...) and requires each
mutation to be reported, so that the first test cannot pass by checking nothing.
Then mypy, an independent reader, when installed (python3-mypy, scripts/setup.sh): its stubtest
compares the stub with the imported module, and mypy type-checks the Python examples of
docs/embedding.md with the stub (no error) and a few misuses (exactly their errors).

Environment (tests/CMakeLists.txt): PYTHONPATH (the built module, with the stub copied beside
it), ROADCROSS_STUB (python/roadcross.pyi in the source tree).
"""

import ast
import builtins
import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import unittest

import roadcross

STUB = os.environ["ROADCROSS_STUB"]
PYBIND_TYPE = type(roadcross.Map)  # pybind11_builtins.pybind11_type
NO_CONSTRUCTOR = type(object.__init__)  # wrapper_descriptor: pybind11's "No constructor defined"


def normalise(text):
    return " ".join((text or "").split())


# --- types -------------------------------------------------------------------------------------

def parse_pybind_type(text):
    """'Optional[List[roadcross.Vehicle]]' -> ('Optional', (('list', (('Vehicle', ()),)),))."""
    tokens = re.findall(r"[\w.]+|[\[\],]", text)
    pos = 0

    def node():
        nonlocal pos
        name = tokens[pos]
        pos += 1
        name = name.removeprefix("roadcross.")
        name = {"List": "list", "Dict": "dict", "Tuple": "tuple", "Set": "set"}.get(name, name)
        args = []
        if pos < len(tokens) and tokens[pos] == "[":
            pos += 1
            while tokens[pos] != "]":
                args.append(node())
                if tokens[pos] == ",":
                    pos += 1
            pos += 1
        return (name, tuple(args))

    result = node()
    if pos != len(tokens):
        raise ValueError(f"cannot parse pybind11 type {text!r}")
    return result


def stub_type(annotation):
    """An ast annotation of the stub in the same form; Literal[...] keeps its values."""
    if isinstance(annotation, ast.Constant):
        if annotation.value is None:
            return ("None", ())
        if isinstance(annotation.value, str):  # forward reference
            return stub_type(ast.parse(annotation.value, mode="eval").body)
    if isinstance(annotation, ast.Name):
        return (annotation.id, ())
    if isinstance(annotation, ast.Attribute):
        return (ast.unparse(annotation), ())
    if isinstance(annotation, ast.Subscript):
        head = ast.unparse(annotation.value)
        index = annotation.slice
        elts = index.elts if isinstance(index, ast.Tuple) else [index]
        if head == "Literal":
            return ("Literal", tuple(ast.literal_eval(e) for e in elts))
        return (head, tuple(stub_type(e) for e in elts))
    if isinstance(annotation, ast.BinOp) and isinstance(annotation.op, ast.BitOr):
        return ("Union", (stub_type(annotation.left), stub_type(annotation.right)))
    raise ValueError(f"unsupported annotation {ast.unparse(annotation)}")


def type_matches(stub, pybind, parameter):
    """Whether the stub's type says what pybind11 says, pybind11's spelling being coarser."""
    head, args = stub
    if head == "Literal":  # pybind11 reports the value type: str for 'GO' | 'WAIT'
        kinds = {type(a).__name__ for a in args}
        return len(kinds) == 1 and pybind == (kinds.pop(), ())
    if pybind == ("object", ()):  # py::object: pybind11 says nothing more
        return True
    if pybind[0] == "Optional":
        inner = None
        if head == "Optional":
            inner = args[0]
        elif head == "Union" and len(args) == 2 and ("None", ()) in args:
            inner = args[0] if args[1] == ("None", ()) else args[1]
        return inner is not None and type_matches(inner, pybind[1][0], parameter)
    if pybind == ("os.PathLike", ()):  # std::filesystem::path: PyUnicode_FSConverter's types
        return head == "Union" and {a[0] for a in args} == {"str", "bytes", "os.PathLike"}
    if not pybind[1] and pybind[0] in ("tuple", "dict", "list", "Iterator"):
        return head == pybind[0]  # py::tuple, py::dict, py::iterator: the stub is more exact
    if parameter and pybind[0] == "list" and head == "Sequence":
        head = "list"  # the list caster accepts any sequence (not str)
    return head == pybind[0] and len(args) == len(pybind[1]) and all(
        type_matches(s, p, parameter) for s, p in zip(args, pybind[1]))


# --- signatures --------------------------------------------------------------------------------

def split_top_level(text):
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += ch == "["
        depth -= ch == "]"
        if ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def pybind_signature(function):
    """[(name, type, default text or None, keyword_only)], return type, user docstring."""
    doc = function.__doc__
    first, _, rest = doc.partition("\n")
    match = re.fullmatch(r"(\w+)\((.*)\) -> (.+)", first)
    if not match:
        raise ValueError(f"{function!r}: no pybind11 signature in {first!r}")
    params, keyword_only = [], False
    for part in split_top_level(match.group(2)):
        if part == "*":
            keyword_only = True
            continue
        name, _, annotation = part.partition(": ")
        annotation, _, default = annotation.partition(" = ")
        params.append((name, parse_pybind_type(annotation), default or None, keyword_only))
    return params, parse_pybind_type(match.group(3)), rest.strip()


def stub_parameters(fn):
    """[(name, annotation node, default node or None, kind)], kind in posonly/normal/kwonly."""
    a = fn.args
    positional = [(p, "posonly") for p in a.posonlyargs] + [(p, "normal") for p in a.args]
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    out = [(p.arg, p.annotation, d, kind) for (p, kind), d in zip(positional, defaults)]
    out += [(p.arg, p.annotation, d, "kwonly") for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.vararg or a.kwarg:
        out.append(("*args/**kwargs", None, None, "variadic"))
    return out


def compare_signature(where, fn, function, is_method):
    problems = []
    pybind, returns, doc = pybind_signature(function)
    stub = stub_parameters(fn)
    if len(stub) != len(pybind):
        return [f"{where}: stub has {len(stub)} parameters {[s[0] for s in stub]}, binding "
                f"{len(pybind)} {[p[0] for p in pybind]}"]
    for i, ((s_name, s_type, s_default, s_kind), (p_name, p_type, p_default, p_kwonly)) in \
            enumerate(zip(stub, pybind)):
        at = f"{where}({s_name})"
        if is_method and i == 0:
            if s_name != "self" or s_kind == "kwonly" or s_type is not None:
                problems.append(f"{at}: first parameter must be an unannotated self")
            continue
        if re.fullmatch(r"arg\d+", p_name):  # no py::arg: positional only, name not callable
            if s_kind != "posonly":
                problems.append(f"{at}: binding parameter {p_name} has no name: make it "
                                "positional-only (/)")
        elif s_name != p_name:
            problems.append(f"{at}: binding calls it {p_name}")
        elif (s_kind == "kwonly") != p_kwonly or s_kind == "posonly":
            problems.append(f"{at}: stub kind {s_kind}, binding "
                            f"{'keyword-only' if p_kwonly else 'positional-or-keyword'}")
        if (s_default is None) != (p_default is None):
            problems.append(f"{at}: default in stub {ast.unparse(s_default) if s_default else None}"
                            f", in binding {p_default}")
        elif s_default is not None:
            s_value, p_value = ast.literal_eval(s_default), ast.literal_eval(p_default)
            if type(s_value) is not type(p_value) or s_value != p_value:
                problems.append(f"{at}: default {s_value!r} in stub, {p_value!r} in binding")
        if s_type is None:
            problems.append(f"{at}: no annotation")
        elif not type_matches(stub_type(s_type), p_type, parameter=True):
            problems.append(f"{at}: stub type {ast.unparse(s_type)}, binding {p_type}")
    if fn.returns is None or not type_matches(stub_type(fn.returns), returns, parameter=False):
        problems.append(f"{where}: stub returns {fn.returns and ast.unparse(fn.returns)}, "
                        f"binding {returns}")
    if normalise(ast.get_docstring(fn)) != normalise(doc):
        problems.append(f"{where}: docstring differs from the binding's:\n  stub:    "
                        f"{normalise(ast.get_docstring(fn))!r}\n  binding: {normalise(doc)!r}")
    return problems


# --- the whole stub ----------------------------------------------------------------------------

def members_of(cls_node):
    """name -> (kind, node) for a stub class: property, method or attribute."""
    out = {}
    for node in cls_node.body:
        if isinstance(node, ast.FunctionDef):
            decorators = [ast.unparse(d) for d in node.decorator_list]
            out[node.name] = ("property" if decorators == ["property"] else "method", node)
        elif isinstance(node, ast.AnnAssign):
            out[node.target.id] = ("attribute", node)
    return out


def binding_members(cls):
    out = {}
    for name, value in vars(cls).items():
        if name in ("__doc__", "__module__", "__weakref__", "__dict__"):
            continue
        if name == "__init__" and isinstance(value, NO_CONSTRUCTOR):
            continue  # no py::init: pybind11's placeholder that raises TypeError
        out[name] = ("property" if isinstance(value, property) else "method", value)
    return out


def check_property(where, fn, prop):
    problems = []
    returns = parse_pybind_type(prop.fget.__doc__.strip().rpartition(" -> ")[2])
    if [a.arg for a in fn.args.args] != ["self"] or fn.returns is None:
        return [f"{where}: a property is `def {fn.name}(self) -> T`"]
    stub = stub_type(fn.returns)
    if not type_matches(stub, returns, parameter=False):
        problems.append(f"{where}: stub type {ast.unparse(fn.returns)}, binding {returns}")
    if not normalise(prop.__doc__):
        problems.append(f"{where}: the binding gives no docstring (give one with the unit)")
    if normalise(ast.get_docstring(fn)) != normalise(prop.__doc__):
        problems.append(f"{where}: docstring {ast.get_docstring(fn)!r}, binding {prop.__doc__!r}")
    if stub[0] == "Literal" and set(stub[1]) != set(re.findall(r"'(\w+)'", prop.__doc__ or "")):
        problems.append(f"{where}: Literal values {sorted(stub[1])} are not the documented ones "
                        f"{prop.__doc__!r}")
    return problems


def check_annotation_names(tree):
    """Every name used in an annotation is imported, a builtin or a class of the stub."""
    known = set(dir(builtins))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            known |= {a.asname or a.name for a in node.names}
        elif isinstance(node, ast.Import):
            known |= {a.asname or a.name for a in node.names}
        elif isinstance(node, ast.ClassDef):
            known.add(node.name)
    problems = []
    for node in ast.walk(tree):
        annotations = []
        if isinstance(node, ast.arg):
            annotations.append(node.annotation)
        elif isinstance(node, ast.FunctionDef):
            annotations.append(node.returns)
        elif isinstance(node, ast.AnnAssign):
            annotations.append(node.annotation)
        for annotation in filter(None, annotations):
            for name in ast.walk(annotation):  # Literal's values are constants, not names
                if isinstance(name, ast.Name) and name.id not in known:
                    problems.append(f"line {name.lineno}: {name.id} is not defined in the stub")
    return problems


def check_stub(source):
    """Every difference between the stub's text and the imported module, as messages."""
    tree = ast.parse(source)
    problems = check_annotation_names(tree)
    if normalise(ast.get_docstring(tree)) != normalise(roadcross.__doc__):
        problems.append("module docstring differs from roadcross.__doc__")
    stub_names = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            stub_names[node.name] = ("class", node)
        elif isinstance(node, ast.FunctionDef):
            stub_names[node.name] = ("function", node)
        elif isinstance(node, ast.AnnAssign):
            stub_names[node.target.id] = ("attribute", node)
    public = {n for n in dir(roadcross) if not n.startswith("_")}
    for name in sorted(public - stub_names.keys()):
        problems.append(f"roadcross.{name} is not in the stub")
    for name in sorted(stub_names.keys() - set(dir(roadcross))):
        problems.append(f"the stub's {name} is not in the module")

    for name, (kind, node) in sorted(stub_names.items()):
        if not hasattr(roadcross, name):
            continue
        obj = getattr(roadcross, name)
        where = f"roadcross.{name}"
        if kind == "attribute":
            expected = ast.unparse(node.annotation)
            if type(obj).__name__ != expected:
                problems.append(f"{where}: stub says {expected}, module has {type(obj).__name__}")
        elif kind == "function":
            if isinstance(obj, type) or not callable(obj):
                problems.append(f"{where}: a function in the stub, {type(obj)} in the module")
            else:
                problems += compare_signature(where, node, obj, is_method=False)
        elif not isinstance(obj, type):
            problems.append(f"{where}: a class in the stub, {type(obj)} in the module")
        else:
            problems += check_class(where, node, obj)
    return problems


def check_class(where, node, cls):
    problems = []
    if normalise(ast.get_docstring(node)) != normalise(cls.__doc__):
        problems.append(f"{where}: class docstring differs from the binding's")
    stub_bases = [ast.unparse(b) for b in node.bases]
    real_bases = [b for b in cls.__bases__ if b.__name__ != "pybind11_object"]
    resolved = [getattr(roadcross, b, getattr(builtins, b, None)) for b in stub_bases]
    if resolved != real_bases:
        problems.append(f"{where}: stub bases {stub_bases}, module "
                        f"{[b.__name__ for b in real_bases]}")
    stub = members_of(node)
    if isinstance(cls, PYBIND_TYPE):
        real = binding_members(cls)
        for name in sorted(real.keys() - stub.keys()):
            problems.append(f"{where}.{name} ({real[name][0]}) is not in the stub")
        for name in sorted(stub.keys() - real.keys()):
            problems.append(f"the stub's {where}.{name} is not in the module")
        for name in sorted(real.keys() & stub.keys()):
            (s_kind, s_node), (r_kind, r_value) = stub[name], real[name]
            if s_kind != r_kind:
                problems.append(f"{where}.{name}: a {s_kind} in the stub, a {r_kind} in the module")
            elif r_kind == "property":
                problems += check_property(f"{where}.{name}", s_node, r_value)
            else:
                problems += compare_signature(f"{where}.{name}", s_node, r_value, is_method=True)
    else:
        # An exception class: nothing of its own but `code`, which the module sets on every
        # raised error (checked on one in the test); declared once, on Error.
        allowed = {"code"} if cls is roadcross.Error else set()
        for name in sorted(stub.keys() - allowed):
            problems.append(f"the stub's {where}.{name} is not set by the module")
        if cls is roadcross.Error and ast.unparse(stub.get("code", (0, node))[1]) != "code: str":
            problems.append(f"{where}: declare `code: str` (the StatusCode name)")
    return problems


def read_stub():
    with open(STUB) as f:
        return f.read()


class StubMatchesModule(unittest.TestCase):

    def test_stub_matches_module(self):
        problems = check_stub(read_stub())
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def test_pybind_reports_what_is_checked(self):
        # The checks rest on pybind11's signature lines: make sure they are being parsed.
        params, returns, _ = pybind_signature(roadcross.Map.assess)
        self.assertEqual([p[0] for p in params][:5], ["self", "lat", "lon", "easting", "northing"])
        self.assertTrue(all(p[3] for p in params[1:]))
        self.assertEqual(params[1][1:3], (("Optional", (("float", ()),)), "None"))
        self.assertEqual(returns, ("Assessment", ()))
        self.assertEqual(len(binding_members(roadcross.Assessment)), 41)  # 40 + __repr__

    def test_error_code_is_set(self):
        with self.assertRaises(roadcross.Error) as caught:
            roadcross.Map(os.path.join(os.path.dirname(STUB), "no-such-map.gpkg"))
        self.assertIsInstance(caught.exception.code, str)

    def test_classes_without_constructor(self):
        # The stub declares no __init__ for these: pybind11 refuses to construct them.
        for cls in (roadcross.MapInfo, roadcross.Assessment, roadcross.GapDecision):
            with self.subTest(cls=cls.__name__), self.assertRaises(TypeError):
                cls()

    def test_stub_is_beside_the_built_module(self):
        # What an IDE reads with PYTHONPATH=build/.../python/module: the same text.
        beside = os.path.join(os.path.dirname(roadcross.__file__), "roadcross.pyi")
        self.assertTrue(os.path.isfile(beside), beside)
        with open(beside) as f:
            self.assertEqual(f.read(), read_stub(), "stale copy: rebuild (cmake re-copies it)")


class CheckerCatchesMistakes(unittest.TestCase):
    """Each edit of a correct stub must be reported: the checker does look."""

    # (what, text of the stub, replacement, a word the report must contain)
    MUTATIONS = [
        ("renamed property", "def valid_distance_m(self) -> float:",
         "def valid_distance_mm(self) -> float:", "valid_distance_mm"),
        ("dropped *", "def assess_segment(\n        self,\n        segment_id: int,\n        *,",
         "def assess_segment(\n        self,\n        segment_id: int,", "keyword-only"),
        ("changed default",
         "max_distance_m: float = 1000.0,\n        max_kerb_height_m: Optional[float] = None,\n    ) -> Assessment:",
         "max_distance_m: float = 100.0,\n        max_kerb_height_m: Optional[float] = None,\n    ) -> Assessment:",
         "default 100.0"),
        ("int default for a float", "kerb_margin_m: float = 0.5,", "kerb_margin_m: float = 1,",
         "kerb_margin_m"),
        ("default added", "vx_mps: float,", "vx_mps: float = 0.0,", "vx_mps"),
        ("Optional dropped", "def score(self) -> Optional[int]:", "def score(self) -> int:",
         "Assessment.score"),
        ("parameter type", "segment_id: int,", "segment_id: str,", "segment_id"),
        ("wrong base", "class NoRoadError(Error, LookupError):",
         "class NoRoadError(Error, KeyError):", "NoRoadError"),
        # (Map's close: MapSet has one too, with another docstring.)
        ("missing method", '    def close(self) -> None:\n        """Close the map now',
         '    def _close(self) -> None:\n        """Close the map now', "Map.close"),
        ("wrong return type", ") -> CrossingProgress:", ") -> CrossingPlan:", "monitor"),
        ("Literal value", "Literal['GO', 'WAIT']", "Literal['GO', 'STOP']", "verdict"),
        ("unknown name", "def candidates(self) -> list[Candidate]:",
         "def candidates(self) -> list[Candidat]:", "Candidat is not defined"),
        ("docstring", '"""km/h, or None"""', '"""mph, or None"""', "maxspeed_kmh"),
        ("positional-only dropped", "index: int, /)", "index: int)", "positional-only"),
    ]

    def test_mutations_are_reported(self):
        source = read_stub()
        for what, old, new, word in self.MUTATIONS:
            with self.subTest(what):
                self.assertEqual(source.count(old), 1, f"mutation anchor {old!r}")
                problems = "\n".join(check_stub(source.replace(old, new)))
                self.assertIn(word, problems)


@unittest.skipUnless(importlib.util.find_spec("mypy"),
                     "needs mypy: scripts/setup.sh installs python3-mypy")
class Mypy(unittest.TestCase):

    def mypy(self, module, *args):
        """(return code, output) of `python -m <module> ...` reading the stub (MYPYPATH), with
        a configuration that keeps mypy's cache out of the source tree."""
        with tempfile.TemporaryDirectory() as work:
            config = os.path.join(work, "mypy.ini")
            with open(config, "w") as f:
                f.write(f"[mypy]\ncache_dir = {work}/cache\n")
            env = dict(os.environ, MYPYPATH=os.path.dirname(os.path.abspath(STUB)))
            config_option = "--mypy-config-file" if module == "mypy.stubtest" else "--config-file"
            out = subprocess.run([sys.executable, "-m", module, *args, config_option, config],
                                 env=env, capture_output=True, text=True)
        return out.returncode, out.stdout + out.stderr

    def test_stubtest(self):
        # What a stub cannot say, allowed by name: a pybind11 class's metaclass
        # (pybind11_builtins.pybind11_type), and the placeholder __init__(*args, **kwargs) that
        # raises TypeError in a class without py::init (test_classes_without_constructor).
        allow = []
        for name in dir(roadcross):
            cls = getattr(roadcross, name)
            if isinstance(cls, PYBIND_TYPE):
                allow.append(f"roadcross.{name}")
                if isinstance(vars(cls).get("__init__"), NO_CONSTRUCTOR):
                    allow.append(f"roadcross.{name}.__init__")
        with tempfile.TemporaryDirectory() as work:
            allowlist = os.path.join(work, "allowlist.txt")
            with open(allowlist, "w") as f:
                f.write("\n".join(allow) + "\n")
            code, out = self.mypy("mypy.stubtest", "roadcross", "--allowlist", allowlist)
        self.assertEqual(code, 0, out)

    MISUSE = """import roadcross
m = roadcross.Map("map.gpkg")
m.assess(50.0, 14.4)  # E: coordinates are keyword-only
a = m.assess(lat=50.0, lon=14.4)
score: int = a.score  # E: Optional[int]
e, n = a.road.closest
distance: float = e + n + a.distance_m + len(m.better_place(lat=50.0, lon=14.4))
p = roadcross.PlanePoint(e, n)  # E: keyword-only
roadcross.gap_decision(m.gap_crossing(easting=e, northing=n), [], now_s="0")  # E: str for float
with m:
    name: str = m.info.path
try:
    m.nearest(lat=50.0, lon=14.4)
except roadcross.NoRoadError as error:
    print(error.code.upper())
except LookupError as error:
    print(error.code)  # E: only roadcross.Error has code
"""

    def test_doc_examples_and_misuse(self):
        source = os.path.join(os.path.dirname(__file__), "..", "..")
        with open(os.path.join(source, "docs", "embedding.md")) as f:
            blocks = re.findall(r"```(\w*)\n(.*?)```", f.read(), re.S)
        examples = [body for lang, body in blocks if lang == "python"]
        self.assertGreaterEqual(len(examples), 4)
        with tempfile.TemporaryDirectory() as work:
            files = []
            for i, body in enumerate(examples + [self.MISUSE]):
                files.append(os.path.join(work, f"example{i}.py"))
                with open(files[-1], "w") as f:
                    f.write(body)
            code, out = self.mypy("mypy", "--check-untyped-defs", "--strict-equality",
                                  "--no-error-summary", *files)
        errors = re.findall(r"^(\S+?):(\d+): error:", out, re.M)
        misuse = os.path.basename(files[-1])
        expected = [(misuse, i + 1) for i, line in enumerate(self.MISUSE.splitlines())
                    if "# E:" in line]
        self.assertEqual(sorted((os.path.basename(f), int(n)) for f, n in errors), expected, out)
        self.assertEqual(code, 1, out)


if __name__ == "__main__":
    unittest.main()
