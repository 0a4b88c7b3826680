#!/bin/sh
# Renders every page of a result directory to PNGs with headless Chromium (through
# scripts/screenshot.sh), for a person to look at: DIR/index.html, every DIR/*.html report
# page and every DIR/*-drawing.svg. Prints one line per page; exits 1 if any page failed.
#   scripts/screenshots.sh DIR [OUTDIR]      (OUTDIR defaults to DIR/../screenshots)
# Window sizes: index 1400x2000, report pages 1400x3000, drawings 1200x900.
set -eu
dir=${1:?usage: scripts/screenshots.sh DIR [OUTDIR]}
[ -d "$dir" ] || { echo "no directory $dir" >&2; exit 2; }
out=${2:-$(dirname "$(realpath "$dir")")/screenshots}
mkdir -p "$out"
one=$(dirname "$0")/screenshot.sh
failed=0
shot() { # FILE SIZE
    png=$out/$(basename "${1%.*}").png
    rm -f "$png"
    if sh "$one" "$1" "$png" "$2" >/dev/null 2>&1 && [ -s "$png" ]; then
        echo "ok      $(basename "$1") -> $png"
    else
        echo "FAILED  $(basename "$1")"
        failed=$((failed + 1))
    fi
}
[ -f "$dir/index.html" ] && shot "$dir/index.html" 1400,2000
for f in "$dir"/*.html; do
    [ -e "$f" ] || continue
    [ "$(basename "$f")" = index.html ] && continue
    shot "$f" 1400,3000
done
for f in "$dir"/*-drawing.svg; do
    [ -e "$f" ] || continue
    shot "$f" 1200,900
done
[ "$failed" -eq 0 ] || { echo "$failed page(s) failed" >&2; exit 1; }
