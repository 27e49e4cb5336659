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
#   2. If libboost_python311.so.1.74.0 is not known to the dynamic linker:
#      `apt-get install --no-install-recommends libboost-python1.74.0`
#      (runs `apt-get update` first if the package is not in the apt lists).
#      Every other shared library rs274 needs is either inside the unpacked
#      tree ($LCNC_REF/usr/lib: librs274, libnml, liblinuxcnchal,
#      liblinuxcncini, libpyplugin, libtooldata, libposemath) or part of a
#      stock Debian 12 system (libpython3.11, libstdc++6, libtirpc3, ...).
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
# bookworm version 2.9.0~pre1+git20230208), libboost-python1.74.0 (installed).
# Needs root (or write access to $LCNC_REF and apt) on the first run only.
set -euo pipefail

LCNC_REF="${LCNC_REF:-/opt/linuxcnc-ref}"
RS274="$LCNC_REF/usr/bin/rs274"
TOOL_TBL="$LCNC_REF/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl"

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

if ! ldconfig -p | grep -q 'libboost_python311\.so\.1\.74\.0'; then
    echo "rs274-ref: installing libboost-python1.74.0" >&2
    if ! apt-cache show libboost-python1.74.0 >/dev/null 2>&1; then
        apt-get update >/dev/null
    fi
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
        libboost-python1.74.0 >/dev/null
fi

run_home="$(mktemp -d)"
trap 'rm -rf "$run_home"' EXIT
set +e
HOME="$run_home" LD_LIBRARY_PATH="$LCNC_REF/usr/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
    "$RS274" -t "$TOOL_TBL" "$@"
status=$?
exit "$status"
