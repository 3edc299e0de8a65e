"""The generated NumPy code is in sync with the SymPy derivations, and agrees with lambdify."""

from __future__ import annotations

import difflib
import importlib
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from photolib import codegen
from photolib.derive import CODEGEN_MODULES


def test_generated_files_match_derivations(tmp_path, request):
    if request.config.getoption("--update-generated"):
        codegen.generate(codegen.GENERATED_DIR)
    codegen.generate(tmp_path)
    for path in sorted(tmp_path.glob("*.py")):
        committed = codegen.GENERATED_DIR / path.name
        assert committed.exists(), f"{committed} missing: run `pytest --update-generated`"
        new, old = path.read_text(), committed.read_text()
        if new != old:
            diff = "".join(difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                                str(committed), "regenerated", n=1))
            pytest.fail(f"{committed} is out of date (run `pytest --update-generated` or "
                        f"`make regen`):\n{diff[:4000]}")
    extra = {p.name for p in codegen.GENERATED_DIR.glob("*.py")} - {p.name for p in tmp_path.glob("*.py")}
    assert not extra, f"stale generated files: {extra}"


def test_generation_is_deterministic(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    codegen.generate(a)
    codegen.generate(b)
    for p in a.glob("*.py"):
        assert p.read_text() == (b / p.name).read_text()


@pytest.mark.parametrize("module", CODEGEN_MODULES)
def test_header_names_source_and_hash(module):
    text = (codegen.GENERATED_DIR / f"{module}.py").read_text()
    assert text.startswith(f"# generated from photolib/derive/{module}.py, do not edit\n")
    assert f"# source sha256: {codegen.source_hash(module)}" in text


def _derive_copy(tmp_path):
    """A copy of photolib/derive to edit (the real files stay untouched)."""
    import shutil

    dest = tmp_path / "derive"
    shutil.copytree(codegen.DERIVE_DIR, dest, ignore=shutil.ignore_patterns("__pycache__"))
    return dest


def test_hash_covers_the_derive_modules_a_derivation_imports(tmp_path):
    """The collinearity Jacobians differentiate rotation.py's R: editing rotation.py (or the
    shared spec) must make _generated/collinearity.py stale, editing optics.py must not."""
    assert codegen.derive_dependencies("collinearity") == ("collinearity", "_spec", "rotation")
    assert codegen.derive_dependencies("rotation") == ("rotation", "_spec")
    derive = _derive_copy(tmp_path)
    before = {m: codegen.source_hash(m, derive) for m in CODEGEN_MODULES}
    assert before == {m: codegen.source_hash(m) for m in CODEGEN_MODULES}
    with open(derive / "optics.py", "a") as f:       # imported by none of them
        f.write("\n# an unrelated edit\n")
    assert {m: codegen.source_hash(m, derive) for m in CODEGEN_MODULES} == before
    with open(derive / "rotation.py", "a") as f:
        f.write("\n# an edit of the rotations\n")
    after = {m: codegen.source_hash(m, derive) for m in CODEGEN_MODULES}
    assert after["rotation"] != before["rotation"]
    assert after["collinearity"] != before["collinearity"]
    assert after["distortion"] == before["distortion"]
    with open(derive / "_spec.py", "a") as f:
        f.write("\n# an edit of the spec\n")
    assert codegen.source_hash("distortion", derive) != before["distortion"]


def test_dependencies_are_followed_transitively_and_inside_functions(tmp_path):
    """a imports b at the top, b imports c inside a function, c imports nothing of derive:
    a change to c changes a's hash; imports of other packages are not followed."""
    d = tmp_path / "derive"
    d.mkdir()
    (d / "__init__.py").write_text("NAMES = ()\n")
    (d / "a.py").write_text("import sympy\nfrom photolib.derive import b\n")
    (d / "b.py").write_text("def f():\n    from photolib.derive.c import g\n    return g\n")
    (d / "c.py").write_text("import photolib.rotations\ndef g():\n    return 1\n")
    (d / "e.py").write_text("from photolib.derive import NAMES\nfrom . import c\n")
    assert codegen.derive_dependencies("a", d) == ("a", "b", "c")
    assert codegen.derive_dependencies("e", d) == ("e", "__init__", "c")
    h = codegen.source_hash("a", d)
    (d / "c.py").write_text("import photolib.rotations\ndef g():\n    return 2\n")
    assert codegen.source_hash("a", d) != h
    # once b no longer imports c, c drops out of a's hash
    (d / "b.py").write_text("def f():\n    return 1\n")
    assert codegen.derive_dependencies("a", d) == ("a", "b")
    h = codegen.source_hash("a", d)
    (d / "c.py").write_text("def g():\n    return 3\n")
    assert codegen.source_hash("a", d) == h


@pytest.mark.parametrize("module", CODEGEN_MODULES)
def test_header_lists_the_hashed_modules(module):
    text = (codegen.GENERATED_DIR / f"{module}.py").read_text()
    hashed = ", ".join(f"derive/{d}.py" for d in codegen.derive_dependencies(module))
    assert f"\n# hashed: {hashed}\n" in text


def _cases():
    for module in CODEGEN_MODULES:
        mod = importlib.import_module(f"photolib.derive.{module}")
        for fn in mod.CODEGEN:
            yield pytest.param(module, fn, id=f"{module}.{fn.name}")


@pytest.mark.parametrize("module,fn", list(_cases()))
def test_generated_function_equals_lambdify(module, fn):
    """Each generated function against ``sympy.lambdify(..., cse=True)`` at seeded random inputs."""
    gen = importlib.import_module(f"photolib._generated.{module}")
    generated = getattr(gen, fn.name)
    reference = sp.lambdify(fn.args, fn.full_exprs, modules="numpy", cse=True)
    rng = np.random.default_rng(20261122)
    n = 64
    args = []
    for a in fn.args:
        name = str(a)
        if name in ("Z0",):
            args.append(rng.uniform(50, 100, n))  # camera above the points: N ≠ 0
        elif name in ("c",):
            args.append(rng.uniform(10, 200, n))
        else:
            args.append(rng.uniform(-1.0, 1.0, n))
    got = generated(*args)
    want = reference(*args)
    assert len(got) == len(fn.outputs)
    for name, g, w in zip(fn.output_names, got, want):
        g, w = np.broadcast_to(g, (n,)), np.broadcast_to(np.asarray(w, float), (n,))
        np.testing.assert_allclose(g, w, rtol=1e-11, atol=1e-12, err_msg=f"{fn.name}: {name}")


def test_import_photolib_is_numpy_only_and_fast():
    """``import photolib`` loads no SymPy/SciPy/OpenCV/matplotlib and takes ≤ 0.2 s in all.

    Each run times NumPy's own import and then photolib's on top of it, in a fresh interpreter,
    in CPU seconds of that interpreter (what the import costs, not how busy the other xdist
    worker keeps the machine); the best of seven runs is taken for each share.
    """
    code = ("import sys, time; c0 = time.process_time(); import numpy; c1 = time.process_time(); "
            "import photolib; c2 = time.process_time(); "
            "bad = [m for m in ('sympy', 'matplotlib', 'scipy', 'cv2', 'mpmath', 'ipywidgets') "
            "if m in sys.modules]; print(c1 - c0, c2 - c1, bad)")
    numpy_t, own_t = [], []
    for _ in range(7):
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        a, b, bad = out.stdout.split(" ", 2)
        assert bad.strip() == "[]", f"import photolib pulled in {bad.strip()}"
        numpy_t.append(float(a))
        own_t.append(float(b))
    assert min(own_t) <= 0.05, f"photolib's own import took {min(own_t):.3f} s > 0.05 s"
    total = min(numpy_t) + min(own_t)
    assert total <= 0.2, f"import photolib took {total:.3f} s (NumPy {min(numpy_t):.3f} s) > 0.2 s"


def test_every_public_name_resolves_lazily():
    import photolib

    for name in photolib.__all__:
        obj = getattr(photolib, name)
        assert obj is not None and name in dir(photolib)
    with pytest.raises(AttributeError, match="no attribute 'rotation_zyx'"):
        photolib.rotation_zyx  # noqa: B018 - the access is the test
