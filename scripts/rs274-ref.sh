#!/usr/bin/env bash
# rs274-ref.sh - run LinuxCNC's stand-alone G-code interpreter `rs274` as the
# reference for latheguard.  Usage: scripts/rs274-ref.sh [rs274 args...] FILE
#   e.g. scripts/rs274-ref.sh -g prog.ngc        (batch mode, canon calls on stdout)
#
# What it does (idempotent; every step is skipped when already done):
#   1. If $LCNC_REF/usr/bin/rs274 is missing (LCNC_REF defaults to
#      /opt/linuxcnc-ref): `apt-get download linuxcnc-uspace` into a temp dir
#      and unpack it with `dpkg -x` into $LCNC_REF.  The package is NOT
#      installed (no dpkg -i, none of its ~40 GUI/Tcl/Python dependencies).
#   2. If `ldd` finds a shared library of rs274 (or of the unpacked LinuxCNC
#      libraries it loads) missing: `apt-get install --no-install-recommends
#      libboost-python1.74.0 libpython3.11 libedit2 libstdc++6` (running
#      `apt-get update` first if the apt lists are empty).  On a stock Debian 12
#      only libboost-python1.74.0 was missing.  Everything else rs274 needs is
#      inside the unpacked tree ($LCNC_REF/usr/lib: librs274, libnml,
#      liblinuxcnchal, liblinuxcncini, libpyplugin, libtooldata, libposemath).
#   3. Runs `$LCNC_REF/usr/bin/rs274 -t <default tool table> "$@"` with
#        LD_LIBRARY_PATH=$LCNC_REF/usr/lib   (the unpacked LinuxCNC libraries)
#        HOME=<fresh temp dir>               (rs274 creates $HOME/.tool.mmap;
#                                             a private HOME lets runs go in
#                                             parallel; removed afterwards)
#      No INI file is used.  `-t` points at the packaged sample tool table
#      ($LCNC_REF/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl,
#      the path rs274 has compiled in as its default, which does not exist
#      because the package is only unpacked); without it rs274 prints
#      "executing" and exits 1.  A `-t` given by the caller comes later on the
#      command line and wins (getopt: last one counts).
#   rs274's exit status is passed through.  rs274 itself prints "executing"
#   on stderr; canonical calls go to stdout.
#
# Debian packages used: linuxcnc-uspace (downloaded + unpacked only, Debian 12
# bookworm version 2.9.0~pre1+git20230208); installed when missing:
# libboost-python1.74.0, libpython3.11, libedit2, libstdc++6 (and their
# dependencies, pulled in by apt).
# Needs root (or write access to $LCNC_REF and apt) on the first run only.
set -euo pipefail

LCNC_REF="${LCNC_REF:-/opt/linuxcnc-ref}"
RS274="$LCNC_REF/usr/bin/rs274"
TOOL_TBL="$LCNC_REF/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl"
RUNTIME_PKGS="libboost-python1.74.0 libpython3.11 libedit2 libstdc++6"

if [ ! -x "$RS274" ]; then
    echo "rs274-ref: unpacking linuxcnc-uspace into $LCNC_REF" >&2
    dl="$(mktemp -d)"
    (
        cd "$dl"
        if ! apt-get download linuxcnc-uspace >/dev/null 2>&1; then
            apt-get update >/dev/null
            apt-get download linuxcnc-uspace >/dev/null
        fi
    )
    mkdir -p "$LCNC_REF.tmp"
    dpkg -x "$dl"/linuxcnc-uspace_*.deb "$LCNC_REF.tmp"
    rm -rf "$dl" "$LCNC_REF"
    mv "$LCNC_REF.tmp" "$LCNC_REF"
fi

# Shared libraries missing for rs274 (ldd lists the whole dependency tree,
# including what the unpacked LinuxCNC libraries need).
missing_libs() {
    LD_LIBRARY_PATH="$LCNC_REF/usr/lib" ldd "$RS274" | grep 'not found' || true
}
if [ -n "$(missing_libs)" ]; then
    echo "rs274-ref: installing $RUNTIME_PKGS" >&2
    if ! apt-cache show libboost-python1.74.0 >/dev/null 2>&1; then
        apt-get update >/dev/null
    fi
    # shellcheck disable=SC2086
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
        $RUNTIME_PKGS >/dev/null
    if [ -n "$(missing_libs)" ]; then
        echo "rs274-ref: still missing: $(missing_libs)" >&2
        exit 127
    fi
fi

run_home="$(mktemp -d)"
trap 'rm -rf "$run_home"' EXIT
set +e
HOME="$run_home" LD_LIBRARY_PATH="$LCNC_REF/usr/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
    "$RS274" -t "$TOOL_TBL" "$@"
status=$?
exit "$status"
