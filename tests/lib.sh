# What the shell tests share. A test sources it after its `set` line:
#     . "$(dirname "$0")/../lib.sh"
# and then calls what it needs. ctest counts exit code 77 as a skip (SKIP_RETURN_CODE).

# Skip unless $WEDGE names the wedge binary (ctest passes it in the environment).
require_wedge() {
    if [ -z "${WEDGE:-}" ] || [ ! -x "$WEDGE" ]; then
        echo "skip: no wedge binary (WEDGE='${WEDGE:-}')"
        exit 77
    fi
}

# T: a fresh directory for the test's files, removed when the script exits.
make_temp_dir() {
    T=$(mktemp -d)
    trap 'rm -rf "$T"' EXIT
}

# check DESCRIPTION EXPECTED_RC ACTUAL_RC: a wrong exit code is reported and sets fail=1
# (the script ends with `exit $fail`).
check() {
    if [ "$2" != "$3" ]; then echo "FAIL: $1: exit $3, expected $2"; fail=1; fi
}

# Skip unless wedge finds an OpenCL device (the filters' tests on a machine without a driver).
require_cl_device() {
    if ! "$WEDGE" info --cl 2>/dev/null | grep -q "device 0"; then
        echo "skip: no OpenCL device"
        exit 77
    fi
}

# relmse REF TEST: wedge compare's relMSE of TEST against REF (empty when it cannot be read).
relmse() {
    "$WEDGE" compare "$1" "$2" --json | sed -n 's/.*"relmse": \([^,]*\),.*/\1/p'
}
