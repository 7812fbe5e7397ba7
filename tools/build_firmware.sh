#!/usr/bin/env bash
# tools/build_firmware.sh [SKETCH...] - build sketches for the Arduino Mega 2560 (what `make firmware` runs).
#
# Every folder firmware/<Name>/ holding <Name>.ino is a sketch (firmware/libraries/ is the board
# support library shared by the sketches, not a sketch); its .ino says what it is in a marker line,
#     // motion-sketch: <family>        (stepper, filter, servo, ...)
# so any copy under another name is built like its original; an .ino without the marker is
# refused in one line. The examples of lib/ (lib/examples/<Name>/<Name>.ino, the Arduino
# library's examples) and of the libraries in firmware/libraries (firmware/libraries/<Lib>/examples/
# <Name>/<Name>.ino) are built too (they need no marker). Each is compiled by arduino-cli for
# FQBN arduino:avr:mega:cpu=atmega2560 with lib/ and firmware/libraries/* as libraries, into
# build/firmware/<Name>/<Name>.ino.{elf,hex}. A compiler warning located in our own code
# (firmware/ or lib/) fails the build; warnings inside Debian's Arduino core are not ours and
# are ignored. At the end a table of flash and SRAM use is printed.
#
# A SKETCH argument is a sketch name (firmware/<Name>), the path of a folder <Name> holding <Name>.ino
# anywhere (a sketch of your own: no marker needed outside firmware/), lib/examples/<Name> or
# firmware/libraries/<Lib>/examples/<Name>. FIRMWARE_SRC names
# another folder of sketches (default firmware/; the libraries are always this tree's).
# Extra compile-time options for every sketch can be given in FIRMWARE_DEFINES, e.g.
#   FIRMWARE_DEFINES="-DSTEPPER_LED_MIRROR=0" tools/build_firmware.sh LeibRampStepper
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
CLI="$ROOT/.tools/arduino-cli"
FQBN="arduino:avr:mega:cpu=atmega2560"
OUT="${FIRMWARE_OUT:-build/firmware}"
[ -x "$CLI" ] || { echo "build_firmware: arduino-cli not found at .tools/arduino-cli: run 'make setup' first" >&2; exit 1; }

SRC="${FIRMWARE_SRC:-firmware}"
MARKER_RE='^[[:space:]]*//[[:space:]]*motion-sketch:[[:space:]]*[A-Za-z0-9_-]+[[:space:]]*$'
all_sketches() {
    for d in "$SRC"/*/; do
        n=$(basename "$d")
        [ -f "$d$n.ino" ] && echo "$n"
    done
    for d in lib/examples/*/ firmware/libraries/*/examples/*/; do
        n=$(basename "$d")
        [ -f "$d$n.ino" ] && echo "${d%/}"
    done
}
# the folder of a SKETCH argument: a sketch's name (firmware/<Name>), an example's folder, or the path
# of any folder holding <Name>/<Name>.ino (a sketch of your own elsewhere: built like an example)
sketch_dir() {
    case "$1" in
        lib/examples/* | firmware/libraries/*/examples/*) echo "$1" ;;
        */*) echo "${1%/}" ;;
        *) echo "$SRC/$1" ;;
    esac
}
if [ $# -gt 0 ]; then sketches=("$@"); else mapfile -t sketches < <(all_sketches); fi
[ ${#sketches[@]} -gt 0 ] || { echo "build_firmware: no sketches under firmware/" >&2; exit 1; }

libs=(--library lib)
for l in firmware/libraries/*/; do [ -d "$l" ] && libs+=(--library "${l%/}"); done
for l in ${FIRMWARE_EXTRA_LIBS:-}; do libs+=(--library "$l"); done

# Debian's core needs arduino-ctags and DECIMAL_DIG (its packaged ctags path; the C library's macro).
# Our own warning flags go in the same property so that the platform's value is not lost.
props=(
    --build-property "tools.ctags.path=/usr/bin"
    --build-property "tools.ctags.cmd.path=/usr/bin/arduino-ctags"
    --build-property "compiler.cpp.extra_flags=-DDECIMAL_DIG=__DECIMAL_DIG__ ${FIRMWARE_DEFINES:-}"
    --build-property "compiler.c.extra_flags=${FIRMWARE_DEFINES:-}"
    --build-property "compiler.S.extra_flags=${FIRMWARE_DEFINES:-}"
)

mkdir -p "$OUT"
failed=0
table=()
for arg in "${sketches[@]}"; do
    dir=$(sketch_dir "$arg")
    s=$(basename "$arg")
    if [ ! -f "$dir/$s.ino" ]; then
        other=("$dir"/*.ino)
        if [ -d "$dir" ] && [ ${#other[@]} -eq 1 ] && [ -f "${other[0]}" ]; then
            echo "build_firmware: $dir holds $(basename "${other[0]}"), not $s.ino: rename it to $s.ino (a sketch's .ino must be named like its folder)" >&2
        else
            echo "build_firmware: no sketch $dir/$s.ino; sketches: $(all_sketches | tr '\n' ' ')" >&2
        fi
        failed=1; continue
    fi
    case "$dir" in
        lib/examples/* | firmware/libraries/*/examples/*) ;;
        "$SRC"/*) if ! grep -Eq "$MARKER_RE" "$dir/$s.ino"; then
               echo "build_firmware: $dir/$s.ino has no marker line '// motion-sketch: <family>' (stepper, multiaxis, filter, servo, library): add it at the top so the tools know what the sketch is (a sketch of your own on MotionStepper: library)" >&2
               failed=1; continue
           fi ;;
    esac
    log="$OUT/$s.log"
    mkdir -p "$OUT/$s"
    "$CLI" --config-file arduino-cli.yaml compile --fqbn "$FQBN" --warnings all "${libs[@]}" "${props[@]}" \
        --build-path "$OUT/.arduino-build/$s" --output-dir "$OUT/$s" "$dir" >"$log" 2>&1
    rc=$?
    # arduino-cli's own noise on a machine without Arduino's servers (discoveries, indexes).
    grep -v -E '^Error initializing instance: (Error loading hardware platform: discovery|Loading index file)' "$log" > "$log.clean"
    # ours: the project's files and the sketch's own folder (a sketch of your own outside the tree too)
    absdir=$(cd "$dir" && pwd); realdir=$(cd "$dir" && pwd -P)
    ours=$({ grep -E '(warning|error):' "$log.clean" | grep -E "($ROOT/)?(firmware|lib)/|$SRC/"
             grep -E '(warning|error):' "$log.clean" | grep -F -e "$absdir/" -e "$realdir/"; } | sort -u || true)
    if [ $rc -ne 0 ]; then
        echo "FAIL $s: compile failed" >&2
        grep -E '(error|Error)' "$log.clean" | head -20 >&2
        failed=1; continue
    fi
    if [ -n "$ours" ]; then
        echo "FAIL $s: warnings in our code:" >&2
        echo "$ours" >&2
        failed=1; continue
    fi
    elf="$OUT/$s/$s.ino.elf"
    # Flash = .text + .data; SRAM = .data + .bss (static use; the stack comes on top).
    read -r text data bss < <(avr-size -A "$elf" | awk '$1==".text"{t=$2} $1==".data"{d=$2} $1==".bss"{b=$2} END{print t+0, d+0, b+0}')
    flash=$((text + data)); sram=$((data + bss))
    table+=("$(awk -v n="$s" -v f="$flash" -v r="$sram" 'BEGIN{printf "%-24s %8d %6.1f%% %8d %6.1f%%", n, f, f*100/253952, r, r*100/8192}')")
done

if [ ${#table[@]} -gt 0 ]; then
    echo
    printf '%-24s %8s %7s %8s %7s\n' "sketch (ATmega2560)" "flash B" "of 248K" "SRAM B" "of 8K"
    printf '%s\n' "${table[@]}"
    echo "(flash = .text+.data of 253952 B usable with the bootloader; SRAM = .data+.bss, static, of 8192 B)"
    echo "outputs: $OUT/<Sketch>/<Sketch>.ino.{elf,hex}"
fi
exit $failed
