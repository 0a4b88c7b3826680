#!/bin/sh
# Renders a batch report (index.html) with Debian's headless Chromium and writes a PNG.
#   scripts/screenshot.sh [DIR/index.html] [OUT.png] [WIDTH,HEIGHT]
# (any page or SVG file; the window is 1400,2000 unless given).
# Installs chromium with apt-get when it is missing (needs root). No network is used by the
# page itself: it is self-contained (inline SVG and CSS).
set -eu
page=${1:-results/index.html}
png=${2:-${page%.html}.png}
size=${3:-1400,2000}
if ! command -v chromium >/dev/null 2>&1; then
    apt-get install -y chromium
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
    --disable-component-update --no-first-run --disable-sync \
    --user-data-dir="$profile" --window-size="$size" \
    --screenshot="$(realpath -m "$png")" "file://$(realpath "$page")" 2>/dev/null
echo "wrote $png"
