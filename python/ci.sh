#!/usr/bin/env bash
# The Python bindings from scratch: a fresh virtual environment in a temporary folder, maturin,
# NumPy and pytest from PyPI, a release wheel of this crate installed into it, then the tests
# (pymuvr, the optional oracle, is installed when it builds; nir, for neurotac.nir, when it
# installs). Needs Python ≥ 3.9 with venv and a Rust toolchain. Prints "skipped: <reason>" and
# exits 0 when Python, venv, pip or the package registries cannot be used; exits non-zero when
# the build or a test fails.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"

skip() {
    echo "skipped: $*"
    exit 0
}

command -v python3 >/dev/null 2>&1 || skip "python3 is not installed"
python3 -c 'import sys; sys.exit(sys.version_info < (3, 9))' \
    || skip "python3 is $(python3 -V 2>&1), the bindings need Python ≥ 3.9"
command -v cargo >/dev/null 2>&1 || { echo "error: cargo is not installed (see the README's quick start)"; exit 1; }

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "== fresh virtual environment in $work/venv"
python3 -m venv "$work/venv" >"$work/venv.log" 2>&1 \
    || skip "python3 cannot create a virtual environment ($(tail -n 1 "$work/venv.log"); Debian: apt-get install python3-venv)"
py="$work/venv/bin/python"
"$py" -m pip --version >/dev/null 2>&1 || skip "the virtual environment has no pip"

echo "== pip install maturin numpy pytest"
"$py" -m pip install -q --disable-pip-version-check maturin numpy pytest >"$work/pip.log" 2>&1 \
    || skip "pip cannot install maturin, numpy and pytest (no access to PyPI?): $(tail -n 1 "$work/pip.log")"

echo "== crates"
if ! cargo fetch --quiet >"$work/fetch.log" 2>&1; then
    cargo metadata --offline --no-deps --format-version 1 >/dev/null \
        || { cat "$work/fetch.log"; echo "error: the crate's manifests are invalid"; exit 1; }
    skip "cargo cannot download the crates (no access to crates.io?): $(tail -n 1 "$work/fetch.log")"
fi

echo "== maturin build --release"
"$work/venv/bin/maturin" build --release --interpreter "$py" --out "$work/wheels"
"$py" -m pip install -q --disable-pip-version-check --no-index --find-links "$work/wheels" neurotac

echo "== pymuvr (optional oracle of the Van Rossum tests)"
if "$py" -m pip install -q --disable-pip-version-check wheel setuptools >"$work/pymuvr.log" 2>&1 \
    && "$py" -m pip install -q --disable-pip-version-check --no-build-isolation pymuvr >>"$work/pymuvr.log" 2>&1; then
    echo "pymuvr installed"
else
    echo "pymuvr could not be installed ($(tail -n 1 "$work/pymuvr.log")); its comparison is skipped"
fi

echo "== nir (optional: neurotac.nir and its tests; needs Python ≥ 3.10)"
if "$py" -m pip install -q --disable-pip-version-check "nir>=1.0,<2" >"$work/nir.log" 2>&1; then
    echo "nir installed"
else
    echo "nir could not be installed ($(tail -n 1 "$work/nir.log")); the NIR tests are skipped"
fi

echo "== matplotlib (optional: the Python tutorial's figure, python/examples/taxel_afferents.py)"
if "$py" -m pip install -q --disable-pip-version-check matplotlib >"$work/mpl.log" 2>&1; then
    echo "matplotlib installed"
else
    echo "matplotlib could not be installed ($(tail -n 1 "$work/mpl.log")); the tutorial draws no figure"
fi

echo "== pytest"
# From the temporary folder, so that the installed package is imported, not the source folder.
cd "$work"
"$py" -m pytest -q -rs "$here/tests"
