#!/usr/bin/env bash
# The Python side of CI: install mtwin-ray (with its test extra) into a venv and run its tests
# against the release binary.
#
#   bash python/ci.sh [MTWIN_BIN]
#
# MTWIN_BIN defaults to ${CARGO_TARGET_DIR:-$HOME/.cache/mtwin-target}/release/mtwin: run
# `cargo build --release` first. The venv (${MTWIN_VENV:-$HOME/.cache/mtwin-venv}) is reused
# between runs: with it, an install only rebuilds this package (~5 s); a new one downloads ray
# and pyarrow (~20-25 s here, where pip's HTTP cache stays empty).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here/.."

bin="${1:-${MTWIN_BIN:-${CARGO_TARGET_DIR:-$HOME/.cache/mtwin-target}/release/mtwin}}"
[ -x "$bin" ] || { echo "python/ci.sh: no mtwin binary at $bin (cargo build --release first)" >&2; exit 1; }
export MTWIN_BIN="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"

venv="${MTWIN_VENV:-$HOME/.cache/mtwin-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import sys' 2>/dev/null; then
  echo "== python venv $venv"
  rm -rf "$venv"
  "$python" -m venv "$venv"
fi

echo "== pip install ./python[test]"
start=$SECONDS
# Not editable: the tests import the installed package, as a user would. setuptools builds in
# python/build, whose leftovers (a module since removed) would be installed too: start clean.
rm -rf python/build python/mtwin_ray.egg-info
"$venv/bin/python" -m pip install -q --disable-pip-version-check ./python[test]
echo "   ($((SECONDS - start)) s)"

echo "== pytest python/tests (MTWIN_BIN=$MTWIN_BIN)"
export RAY_USAGE_STATS_ENABLED=0
# Recent Ray (2.60; not 2.40) turns token auth on for a new local cluster and writes
# ~/.ray/auth_token.
export RAY_AUTH_MODE="${RAY_AUTH_MODE:-disabled}"
# pytest's own script, from the repo root: neither puts python/ on sys.path, so the tests
# import the installed package.
exec "$venv/bin/pytest" -q -p no:cacheprovider python/tests
