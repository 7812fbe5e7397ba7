#!/usr/bin/env bash
# tools/setup.sh - install everything this project needs on Debian 12 (what `make setup` runs).
#
# Idempotent: every step checks first and only acts when something is missing. Each step prints
# one line; a step that cannot be done stops the script with one line saying what is missing.
# Sources are package registries only: Debian packages, PyPI and the Go module proxy. Arduino's
# download servers are never contacted.
#
#   1. Debian packages (apt-get; sudo when not root)
#   2. Python virtual environment .venv with the pinned requirements.txt
#   3. arduino-cli: one >= 0.35 on PATH is used; otherwise v0.35.3 is built from the Go module
#      proxy into .tools/bin (a Go >= 1.21 toolchain is fetched from the proxy too if needed)
#   4. arduino-cli data/user directories with Debian's AVR core linked in
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
TOOLS="$ROOT/.tools"
ARDUINO_CLI_VERSION=0.35.3
GO_TOOLCHAIN=go1.22.12

step() { printf '==> %s\n' "$*"; }
ok()   { printf '    %s\n' "$*"; }
die()  { printf 'setup: %s\n' "$*" >&2; exit 1; }

# as_root CMD...: runs CMD as root (through sudo when not root); only package installs need it.
as_root() {
    if [ "$(id -u)" -eq 0 ]; then
        "$@"
    elif command -v sudo >/dev/null 2>&1; then
        sudo "$@"
    else
        die "not root and sudo is missing, needed for: $*; run 'make setup' as root or install sudo"
    fi
}

# go_download MODULE@VERSION: the module's directory from the Go module proxy, or dies with Go's reason.
go_download() {
    local go_bin=$1 mod=$2 json dir err
    json=$(cd /tmp && GO111MODULE=on GOFLAGS=-mod=mod GOTOOLCHAIN=local "$go_bin" mod download -json "$mod" 2>&1) || true
    dir=$(printf '%s\n' "$json" | sed -n 's/.*"Dir": *"\(.*\)".*/\1/p' | head -n1)
    if [ -z "$dir" ] || [ ! -d "$dir" ]; then
        err=$(printf '%s\n' "$json" | sed -n 's/.*"Error": *"\(.*\)".*/\1/p' | head -n1)
        [ -n "$err" ] || err=$(printf '%s\n' "$json" | tail -n1)
        die "the Go module proxy did not serve $mod: ${err:-no answer} (GOPROXY=$("$go_bin" env GOPROXY 2>/dev/null))"
    fi
    printf '%s\n' "$dir"
}

# --- 1. Debian packages ------------------------------------------------------------------
DEB_PACKAGES=(
    make gcc g++ libc6-dev git ca-certificates  # host build of motionsim (C and the PID class in C++), tests, the emulator harness
    gcc-avr avr-libc binutils-avr           # AVR compiler and C library
    arduino-core-avr arduino-ctags          # the Arduino AVR core as Debian packages it
    avrdude                                 # flashing a real Mega (make upload)
    simavr libsimavr-dev libelf-dev         # ATmega2560 emulator library (emulator tests)
    libcmocka-dev                           # unit-test framework
    libcjson-dev                            # JSON reader (the PID_v1 vectors' set-ups, sim/pid_vector.c)
    python3 python3-venv                    # plots, spreadsheet, CLI tests
)
step "Debian packages: ${DEB_PACKAGES[*]}"
command -v dpkg-query >/dev/null 2>&1 || die "dpkg-query not found: this script needs Debian 12 (or install the packages listed above by hand)"
missing=()
for p in "${DEB_PACKAGES[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    [ "$status" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    ok "all installed"
else
    ok "installing: ${missing[*]}"
    command -v apt-get >/dev/null 2>&1 || die "apt-get not found; missing Debian packages: ${missing[*]}"
    [ "$(id -u)" -eq 0 ] || command -v sudo >/dev/null 2>&1 \
        || die "not root and sudo is missing; run 'make setup' as root or install sudo (missing Debian packages: ${missing[*]})"
    log=$(mktemp /tmp/motion-setup-apt.XXXXXX)
    as_root apt-get update >"$log" 2>&1 || die "apt-get update failed (is the Debian mirror reachable?); log: $log"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}" >>"$log" 2>&1 \
        || die "apt-get could not install: ${missing[*]}; log: $log"
    rm -f "$log"
    ok "installed"
fi

# --- 2. Python virtual environment -----------------------------------------------------
step "Python virtual environment .venv (requirements.txt, pinned)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv || die "python3 -m venv failed: the Debian package python3-venv is missing"
fi
stamp=.venv/.requirements.installed
if [ -f "$stamp" ] && cmp -s requirements.txt "$stamp"; then
    ok "up to date"
else
    .venv/bin/pip install --disable-pip-version-check -q -r requirements.txt \
        || die "pip could not install requirements.txt from PyPI"
    cp requirements.txt "$stamp"
    ok "installed"
fi

# --- 3. arduino-cli ---------------------------------------------------------------------
version_ge() { # version_ge A B: true when A >= B (dotted numbers)
    [ "$(printf '%s\n%s\n' "$2" "$1" | sort -V | head -n1)" = "$2" ]
}
cli_version() { # prints the version number an arduino-cli binary reports, or nothing
    "$1" version 2>/dev/null | sed -n 's/.*Version: *\([0-9][0-9.]*\).*/\1/p' | head -n1
}
step "arduino-cli >= 0.35"
mkdir -p "$TOOLS/bin"
have=""
if [ -x "$TOOLS/bin/arduino-cli" ] && version_ge "$(cli_version "$TOOLS/bin/arduino-cli")" 0.35; then
    have="$TOOLS/bin/arduino-cli"
elif sys=$(command -v arduino-cli 2>/dev/null) && v=$(cli_version "$sys") && [ -n "$v" ] && version_ge "$v" 0.35; then
    have="$sys"
fi
if [ -n "$have" ]; then
    ok "using $have ($(cli_version "$have"))"
else
    # A Go toolchain >= 1.21 is needed (arduino-cli's go.mod says go 1.21). Debian 12 ships 1.19,
    # which is still good enough to fetch a newer toolchain from the Go module proxy.
    GO=""
    for g in "$TOOLS/go/bin/go" "$(command -v go 2>/dev/null || true)"; do
        [ -n "$g" ] && [ -x "$g" ] || continue
        gv=$("$g" env GOVERSION 2>/dev/null | sed 's/^go//')
        if [ -n "$gv" ] && version_ge "$gv" 1.21; then GO="$g"; break; fi
    done
    if [ -z "$GO" ]; then
        if ! command -v go >/dev/null 2>&1; then
            ok "installing Debian's golang-go to bootstrap a newer Go"
            { as_root apt-get update && as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y golang-go; } >/dev/null 2>&1 \
                || die "no Go toolchain: apt-get could not install golang-go"
        fi
        ok "fetching Go toolchain $GO_TOOLCHAIN from the Go module proxy"
        tdir=$(go_download "$(command -v go)" "golang.org/toolchain@v0.0.1-$GO_TOOLCHAIN.linux-$(go env GOARCH)") || exit 1
        rm -rf "$TOOLS/go" && cp -r "$tdir" "$TOOLS/go" && chmod -R u+w "$TOOLS/go"
        chmod +x "$TOOLS"/go/bin/* "$TOOLS"/go/pkg/tool/*/*
        GO="$TOOLS/go/bin/go"
    fi
    ok "building arduino-cli $ARDUINO_CLI_VERSION from the Go module proxy with $GO (about a minute)"
    src=$(go_download "$GO" "github.com/arduino/arduino-cli@v$ARDUINO_CLI_VERSION") || exit 1
    (cd "$src" && GOFLAGS=-buildvcs=false GOTOOLCHAIN=local "$GO" build \
        -ldflags "-X github.com/arduino/arduino-cli/version.versionString=$ARDUINO_CLI_VERSION" \
        -o "$TOOLS/bin/arduino-cli" .) || die "building arduino-cli $ARDUINO_CLI_VERSION failed"
    ok "built $TOOLS/bin/arduino-cli ($(cli_version "$TOOLS/bin/arduino-cli"))"
fi
echo "$have" | grep -q . || have="$TOOLS/bin/arduino-cli"
ln -sfn "$have" "$TOOLS/arduino-cli"   # the one path the Makefile uses

# --- 4. Arduino directories and Debian's AVR core ---------------------------------------
step "arduino-cli directories (.arduino/) with Debian's AVR core"
core=/usr/share/arduino/hardware/arduino
[ -f "$core/avr/platform.txt" ] || die "Debian's AVR core is missing at $core (package arduino-core-avr)"
mkdir -p .arduino/data .arduino/user/hardware .arduino/staging
ln -sfn "$core" .arduino/user/hardware/arduino
# Empty indexes: without them arduino-cli tries to download them on every call.
[ -f .arduino/data/package_index.json ] || echo '{"packages":[]}' > .arduino/data/package_index.json
[ -f .arduino/data/library_index.json ] || echo '{"libraries":[]}' > .arduino/data/library_index.json
if "$TOOLS/arduino-cli" --config-file arduino-cli.yaml core list 2>/dev/null | grep -q '^arduino:avr'; then
    ok "arduino-cli sees $("$TOOLS/arduino-cli" --config-file arduino-cli.yaml core list 2>/dev/null | awk '/^arduino:avr/{print $1" "$2}')"
else
    die "arduino-cli does not see the arduino:avr core in .arduino/user/hardware"
fi

step "setup complete; next: make profiles (the standard ramps, filters and servo runs: build/profiles/*.png and profiles.xlsx); make test checks everything (several minutes)"
