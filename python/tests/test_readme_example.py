"""The README's Python example runs as printed and reports an accuracy, not a list of labels."""

import contextlib
import io
import pathlib
import re

import pytest

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


def readme_python_example():
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## From Python") :]
    match = re.search(r"```python\n(.*?)```", section, re.S)
    assert match, "no python block in the README's 'From Python' section"
    return match.group(1)


@pytest.mark.skipif(not README.exists(), reason="the repository's README.md is not beside python/")
def test_the_readme_example_prints_a_leave_one_out_accuracy():
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(readme_python_example(), str(README), "exec"), {})
    printed = out.getvalue().strip()
    match = re.fullmatch(r"leave-one-out accuracy: (\d+\.\d)%", printed)
    assert match, printed
    # 11 textures: well above chance (9 %) on the exact Van Rossum distance.
    assert 50.0 < float(match.group(1)) <= 100.0, printed
