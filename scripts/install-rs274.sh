#!/usr/bin/env bash
# install-rs274.sh [DIR]
#
# Installs LinuxCNC's standalone G-code interpreter `rs274` (the G-code
# oracle of the test suite) into DIR (default /opt/rs274) WITHOUT installing
# LinuxCNC: the Debian packages are fetched with `apt-get download` and
# unpacked with `dpkg -x`; nothing is registered with dpkg.
#
#   DIR/usr/...   unpacked packages (linuxcnc-uspace, libboost-python, and
#                 any shared library or Python stdlib the host lacks)
#   DIR/rs274     wrapper: sets LD_LIBRARY_PATH (and PYTHONHOME) and runs
#                 DIR/usr/bin/rs274 with the caller's arguments, e.g.
#                   DIR/rs274 -t tool.tbl -g prog.ngc [out.txt]
#   DIR/tool.tbl  a small sample tool table (T1..T10)
#
# Idempotent: if DIR/rs274 already works, it only says so.
# Never fails the caller: every problem (no apt, not root, no network,
# package missing, library missing...) is reported on stderr and the script
# exits 0. Callers (tests) must check for DIR/rs274 themselves.
# Needs: bash, apt-get, apt-cache, dpkg (Debian bookworm or similar), and
# root only if the apt package lists have never been downloaded.

set -u

DIR=${1:-/opt/rs274}
ME=install-rs274

say()  { printf '%s: %s\n' "$ME" "$*" >&2; }
give_up() {
    say "$*"
    say "rs274 is NOT installed; tests that need the G-code oracle will be skipped."
    exit 0
}

case "$DIR" in
    /*) ;;
    *) DIR="$(pwd)/$DIR" ;;
esac

# --------------------------------------------------------------------------
# Smoke test: run the wrapper on a tiny program.
smoke_test() {
    local t rc
    [ -x "$DIR/rs274" ] && [ -x "$DIR/usr/bin/rs274" ] || return 1
    t=$(mktemp -d) || return 1
    printf 'T1 P1 Z0 D6\n' > "$t/tool.tbl"
    printf 'G21 G17 G90\nG0 X1 Y2 Z3\nG1 Z-1 F100\nG2 X3 Y2 I1 J0\nM2\n' > "$t/t.ngc"
    "$DIR/rs274" -t "$t/tool.tbl" -g "$t/t.ngc" > "$t/out" 2> "$t/err" < /dev/null
    rc=$?
    if [ $rc -eq 0 ] && grep -q 'ARC_FEED(3.0000, 2.0000, 2.0000, 2.0000' "$t/out"; then
        rm -rf "$t"; return 0
    fi
    SMOKE_ERR="exit code $rc; stderr: $(head -c 600 "$t/err" | tr '\n' ' ')"
    rm -rf "$t"
    return 1
}
SMOKE_ERR=""

if smoke_test; then
    say "rs274 already installed and working: $DIR/rs274"
    exit 0
fi

# --------------------------------------------------------------------------
# Preconditions.
for c in apt-get apt-cache dpkg; do
    command -v "$c" > /dev/null 2>&1 || give_up "'$c' not found: not a Debian-like system (apt unavailable)."
done
ARCH=$(dpkg --print-architecture 2>/dev/null) || give_up "dpkg --print-architecture failed."

mkdir -p "$DIR" 2>/dev/null || give_up "cannot create $DIR (permission denied? run as root or pass a writable folder as \$1)."
[ -w "$DIR" ] || give_up "$DIR is not writable (run as root or pass a writable folder as \$1)."

WORK=$(mktemp -d) || give_up "mktemp failed."
trap 'rm -rf "$WORK"' EXIT
# apt-get download as root drops privileges to _apt: let it write here.
chmod 0777 "$WORK" 2>/dev/null

TIMEOUT=""
command -v timeout > /dev/null 2>&1 && TIMEOUT="timeout 600"
APT_OPTS=(-q -o Acquire::Retries=2 -o Acquire::http::Timeout=30 -o Acquire::https::Timeout=30)

UPDATED=0
apt_update() {
    [ $UPDATED -eq 1 ] && return 1
    UPDATED=1
    if [ "$(id -u)" -ne 0 ]; then
        say "package lists may be missing or stale, but not root: cannot run apt-get update."
        return 1
    fi
    say "running apt-get update ..."
    $TIMEOUT apt-get "${APT_OPTS[@]}" update > "$WORK/update.log" 2>&1 || {
        say "apt-get update failed: $(grep -E '^(E|W|Err):' "$WORK/update.log" | head -n 4 | tr '\n' ' ')"
        return 1
    }
    # apt-get update exits 0 even when a mirror cannot be reached: show why.
    if grep -qE '^(E|W|Err):' "$WORK/update.log"; then
        say "apt-get update warned: $(grep -E '^(E|W|Err):' "$WORK/update.log" | head -n 4 | tr '\n' ' ')"
    fi
    return 0
}

# Is a package known to apt? (updates the lists once if not)
pkg_known() {
    apt-cache show "$1" > /dev/null 2>&1 && return 0
    apt_update && apt-cache show "$1" > /dev/null 2>&1
}

# Download packages into $WORK/debs and unpack them into $DIR.
fetch() {
    local p f
    mkdir -p "$WORK/debs" && chmod 0777 "$WORK/debs"
    rm -f "$WORK"/debs/*.deb
    say "downloading: $*"
    if ! (cd "$WORK/debs" && $TIMEOUT apt-get "${APT_OPTS[@]}" download "$@") > "$WORK/dl.log" 2>&1; then
        if apt_update && (cd "$WORK/debs" && $TIMEOUT apt-get "${APT_OPTS[@]}" download "$@") > "$WORK/dl.log" 2>&1; then
            :
        else
            say "apt-get download failed: $(grep -E '^(E|W):' "$WORK/dl.log" | head -n 4 | tr '\n' ' ')"
            return 1
        fi
    fi
    for f in "$WORK"/debs/*.deb; do
        [ -e "$f" ] || { say "no .deb was downloaded"; return 1; }
        dpkg -x "$f" "$DIR" || { say "dpkg -x $f failed"; return 1; }
    done
    return 0
}

# --------------------------------------------------------------------------
# 1. linuxcnc-uspace and the Boost.Python it was built against.
pkg_known linuxcnc-uspace || give_up "package linuxcnc-uspace is not available from the configured apt sources (Debian bookworm 'main' has it; is the network / mirror reachable?)."
BOOST=$(apt-cache depends linuxcnc-uspace 2>/dev/null \
        | sed -n 's/^ *Depends: \(libboost-python[0-9.]*\)$/\1/p' | head -n 1)
[ -n "$BOOST" ] || BOOST=libboost-python1.74.0
fetch linuxcnc-uspace "$BOOST" || give_up "could not download linuxcnc-uspace / $BOOST."
[ -x "$DIR/usr/bin/rs274" ] || give_up "linuxcnc-uspace unpacked, but $DIR/usr/bin/rs274 is missing."

# --------------------------------------------------------------------------
# 2. Shared libraries the host lacks: ask the loader, download, repeat.
libdirs() {
    local d out=""
    for d in "$DIR/usr/lib" "$DIR"/usr/lib/*-linux-gnu* "$DIR"/lib/*-linux-gnu* "$DIR/lib"; do
        [ -d "$d" ] && out="$out:$d"
    done
    printf '%s' "${out#:}"
}

missing_libs() {
    if command -v ldd > /dev/null 2>&1; then
        LD_LIBRARY_PATH="$(libdirs)" ldd "$DIR/usr/bin/rs274" 2>/dev/null \
            | sed -n 's/^[[:space:]]*\([^ ]*\) => not found.*/\1/p' | sort -u
    else
        LD_LIBRARY_PATH="$(libdirs)" "$DIR/usr/bin/rs274" < /dev/null 2>&1 >/dev/null \
            | sed -n 's/.*error while loading shared libraries: \([^:]*\):.*/\1/p'
    fi
}

# soname -> Debian package (Debian naming policy, plus the odd ones out)
pkg_for_soname() {
    local so=$1 base ver
    case "$so" in
        libz.so.1)             echo zlib1g; return ;;
        libpython3*.so*)       echo "libpython$(printf '%s' "$so" | sed -n 's/^libpython\([0-9.]*[0-9]\)\.so.*/\1/p')"; return ;;
        libboost_python*)      echo "$BOOST"; return ;;
        libstdc++.so.6)        echo libstdc++6; return ;;
        libgcc_s.so.1)         echo libgcc-s1; return ;;
    esac
    base=${so%%.so*}; ver=${so#*.so.}; ver=${ver%%.*}
    base=$(printf '%s' "$base" | tr '_A-Z' '-a-z')
    case "$base" in
        *[0-9]) echo "$base-$ver" ;;
        *)      echo "$base$ver" ;;
    esac
}

for round in 1 2 3 4 5 6; do
    MISSING=$(missing_libs)
    [ -z "$MISSING" ] && break
    PKGS=""
    for so in $MISSING; do
        p=$(pkg_for_soname "$so")
        if pkg_known "$p"; then
            PKGS="$PKGS $p"
        else
            say "shared library $so is missing and no package '$p' is known to apt."
        fi
    done
    [ -n "$PKGS" ] || break
    # shellcheck disable=SC2086
    fetch $(printf '%s\n' $PKGS | sort -u) || give_up "could not download the libraries rs274 needs ($PKGS)."
done
MISSING=$(missing_libs)
[ -z "$MISSING" ] || give_up "shared libraries still missing: $(echo $MISSING)"

# --------------------------------------------------------------------------
# 3. rs274 embeds Python: it needs the Python standard library at start-up.
PYVER=$(LD_LIBRARY_PATH="$(libdirs)" ldd "$DIR/usr/bin/rs274" 2>/dev/null \
        | sed -n 's/^[[:space:]]*libpython\([0-9.]*[0-9]\)\.so.*/\1/p' | head -n 1)
[ -n "$PYVER" ] || PYVER=$(ls "$DIR"/usr/lib/*-linux-gnu*/libboost_python3*.so.* 2>/dev/null \
        | sed -n 's/.*libboost_python3\([0-9]*\)\.so.*/3.\1/p' | head -n 1)
[ -n "$PYVER" ] || PYVER=3.11
if [ ! -f "/usr/lib/python$PYVER/encodings/__init__.py" ] \
   && [ ! -f "$DIR/usr/lib/python$PYVER/encodings/__init__.py" ]; then
    fetch "libpython$PYVER-minimal" "libpython$PYVER-stdlib" \
        || give_up "the Python $PYVER standard library is missing and could not be downloaded."
fi

# --------------------------------------------------------------------------
# 4. The wrapper and a sample tool table.
cat > "$DIR/rs274" <<EOF
#!/bin/sh
# Wrapper written by install-rs274.sh: runs LinuxCNC's standalone G-code
# interpreter from its unpacked packages.
#   usage: \$0 -t tool.tbl -g program.ngc [output.txt]
# (-t is required: without a tool table rs274 prints nothing and exits 1.)
D=\$(dirname "\$(readlink -f "\$0")")
L=""
for d in "\$D/usr/lib" "\$D"/usr/lib/*-linux-gnu* "\$D"/lib/*-linux-gnu* "\$D/lib"; do
    [ -d "\$d" ] && L="\$L:\$d"
done
LD_LIBRARY_PATH="\${L#:}\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
export LD_LIBRARY_PATH
# The embedded Python $PYVER needs its standard library; do not let a
# pyenv/venv PYTHONHOME or PYTHONPATH of the caller leak in.
if [ -f "\$D/usr/lib/python$PYVER/encodings/__init__.py" ]; then
    PYTHONHOME="\$D/usr"
else
    PYTHONHOME=/usr
fi
export PYTHONHOME
unset PYTHONPATH
PYTHONNOUSERSITE=1
export PYTHONNOUSERSITE
exec "\$D/usr/bin/rs274" "\$@"
EOF
chmod 0755 "$DIR/rs274"

if [ ! -f "$DIR/tool.tbl" ]; then
    {
        echo "; sample LinuxCNC tool table: T<tool> P<pocket> Z<length offset> D<diameter> ;comment"
        for i in 1 2 3 4 5 6 7 8 9 10; do
            echo "T$i P$i Z0 D6 ;tool $i"
        done
    } > "$DIR/tool.tbl"
fi

if smoke_test; then
    say "OK: rs274 installed; run it as: $DIR/rs274 -t $DIR/tool.tbl -g program.ngc"
else
    say "rs274 was unpacked into $DIR but does not run: $SMOKE_ERR"
    say "rs274 is NOT usable; tests that need the G-code oracle will be skipped."
fi
exit 0
