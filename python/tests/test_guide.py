"""The guide's pages that hold Python: every ``sh run`` and ``python run`` block of such a page
(README.md, docs/**/*.md) runs in order in a fresh folder, as a reader would run them from a
clone (``examples/`` and ``python/`` are there; ``neurotac`` is this build's binary). A block
tagged ``prints`` shows what it prints: each line a Python block prints is a ``# …`` comment of
the block, each line a shell block prints is on the page (its output block).

The other pages' commands run in cli/tests/guide_commands.rs."""

import contextlib
import io
import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("NEUROTAC_BIN", ROOT / "target" / "release" / "neurotac"))
FENCE = re.compile(r"^```(\S*)([^\n]*)\n(.*?)^```", re.S | re.M)


def pages():
    if not (ROOT / "docs").is_dir():
        return []
    found = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    return [p for p in found if any(b[0] == "python" and "run" in b[1] for b in blocks(p))]


def blocks(page):
    """``(language, tags, code)`` of every fenced block of ``page``."""
    text = page.read_text(encoding="utf-8")
    return [(m.group(1), m.group(2).split(), m.group(3)) for m in FENCE.finditer(text)]


@pytest.mark.skipif(not BIN.is_file(), reason=f"the neurotac command is not built at {BIN}")
@pytest.mark.parametrize("page", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_the_page_runs_as_printed(page, tmp_path, monkeypatch):
    pytest.importorskip("nir")  # the Python and NIR tutorial imports it
    os.symlink(ROOT / "examples", tmp_path / "examples")
    os.symlink(ROOT / "python", tmp_path / "python")
    bin_dir = tmp_path / ".bin"
    bin_dir.mkdir()
    os.symlink(BIN, bin_dir / "neurotac")
    python_dir = pathlib.Path(sys.executable).parent  # `python3` in a block is this one
    env = dict(os.environ, PATH=f"{bin_dir}:{python_dir}:{os.environ.get('PATH', '')}")
    env.setdefault("NEUROTAC_CACHE", str(pathlib.Path(os.environ.get("TMPDIR", "/tmp")) / "neurotac-guide-cache"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("NEUROTAC_CACHE", env["NEUROTAC_CACHE"])
    for language, tags, code in blocks(page):
        if "run" not in tags:
            continue
        if language == "sh":
            done = subprocess.run(["sh", "-e", "-c", code], env=env, capture_output=True, text=True)
            assert done.returncode == 0, f"{page}: {code}\n{done.stderr}"
            if "prints" in tags:
                text = page.read_text(encoding="utf-8")
                for line in done.stdout.splitlines():
                    assert line in text, f"{page}: `{code.strip()}` prints {line!r}, the page does not show it"
        elif language == "python":
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(code, str(page), "exec"), {"__name__": "__guide__"})
            if "prints" in tags:
                for line in out.getvalue().splitlines():
                    assert f"# {line}\n" in code + "\n", f"{page}: prints {line!r}, the page does not show it"
