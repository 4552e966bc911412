# Sourced by gpu_run.sh and verify_run.sh (not run on its own): the environment of a run on a machine with no
# package registry. Expects RESULTS (the results folder, created here) and the repository as the working directory.
# Installs the wheels brought along in .whl/ into /tmp/site (never touching the system), or uses the current
# Python as it is, and links ../shared when the repository carries the tutorial's anchors inside (shared/).
mkdir -p "$RESULTS"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
export PYTHON="${PYTHON:-python3}"

if compgen -G ".whl/*.whl" > /dev/null; then
    "$PYTHON" -m pip install --no-index --no-deps --target /tmp/site .whl/*.whl \
        > "$RESULTS/pip.log" 2>&1 || { echo "wheel install failed: see $RESULTS/pip.log"; exit 1; }
    export PYTHONPATH="$PWD:/tmp/site${PYTHONPATH:+:$PYTHONPATH}"
else
    echo "no .whl/ folder: using the current Python environment as it is"
    export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}"
fi
if [ ! -e ../shared ] && [ -d shared/anchors ]; then ln -s "$PWD/shared" ../shared; fi
