# Sourced by scripts/test.sh and lab/setup_venv.sh: the project's virtual environment
# .venv/ and this checkout's `cushion` package built into it by maturin. Run from the
# repository's top folder.

# Creates .venv/ with $PYTHON (default python3) unless it exists, and upgrades its pip.
venv_create() {
    local python=${PYTHON:-python3}
    [ -x .venv/bin/python ] || "$python" -m venv .venv
    .venv/bin/python -m pip install -q --upgrade pip
}

# Installs the package's dependencies and those of its extras $1 (e.g. "test"), as
# pyproject.toml lists them, without the package: so they can install while the extension
# compiles.
dependencies_install() {
    local extras=${1:-}
    .venv/bin/python - "$extras" <<'PY' | .venv/bin/python -m pip install -q -r /dev/stdin
import sys
try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    from pip._vendor import tomli as tomllib
with open("pyproject.toml", "rb") as f:
    project = tomllib.load(f)["project"]
wanted = list(project["dependencies"])
for extra in filter(None, sys.argv[1].split(",")):
    wanted += project["optional-dependencies"][extra]
print("\n".join(wanted))
PY
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
    local wheel
    wheel=$(ls "$out"/cushion-*.whl)
    # The dependencies as needed, then this build of the package over any earlier one of the
    # same version (forcing only the package: its dependencies stay as they are).
    .venv/bin/python -m pip install -q "$@" "$wheel$extras"
    .venv/bin/python -m pip install -q --force-reinstall --no-deps "$wheel"
    rm -rf "$out"
}
