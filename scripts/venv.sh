# Sourced by scripts/test.sh and lab/setup_venv.sh: the project's virtual environment
# .venv/ and this checkout's `cushion` package built into it by maturin. Run from the
# repository's top folder.

# Creates .venv/ with $PYTHON (default python3) unless it exists, and upgrades its pip.
venv_create() {
    local python=${PYTHON:-python3}
    [ -x .venv/bin/python ] || "$python" -m venv .venv
    .venv/bin/python -m pip install -q --upgrade pip
}

# Builds the wheel (locked crates; Cargo profile $CUSHION_WHEEL_PROFILE, default release) into a
# scratch folder and installs it into .venv/, replacing any earlier build. $1: the extras to
# install with it ("" or e.g. "[test]"); the other arguments go to pip (e.g. --no-deps).
package_install() {
    local extras=$1
    shift
    .venv/bin/python -m pip install -q "maturin>=1.5,<2"
    local out
    out=$(mktemp -d)
    .venv/bin/maturin build --profile "${CUSHION_WHEEL_PROFILE:-release}" --locked --out "$out"
    .venv/bin/python -m pip install -q --force-reinstall "$@" "$(ls "$out"/cushion-*.whl)$extras"
    rm -rf "$out"
}
