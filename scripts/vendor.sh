#!/bin/sh
# The designer page's plotting library (uPlot, MIT), vendored so that the page works offline:
# `npm ci` in web/ installs the version web/package-lock.json pins (its integrity hash
# checked), and its dist files and LICENSE are copied into src/serve/assets/vendor/, which
# the binary embeds (src/serve/assets.rs).
#   scripts/vendor.sh           copy them (after changing web/package.json: `npm install`
#                               in web/ first, to update the lock file)
#   scripts/vendor.sh --check   fail unless the committed copies equal the package's files
#                               (.ci/run: no hand edit of a vendored file)
set -eu
cd "$(dirname "$0")/.."
command -v npm >/dev/null || { echo "npm is required (Node.js)"; exit 1; }
(cd web && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
from=web/node_modules/uplot
to=src/serve/assets/vendor
status=0
for pair in dist/uPlot.iife.min.js:uPlot.iife.min.js dist/uPlot.min.css:uPlot.min.css LICENSE:uPlot.LICENSE; do
    src=$from/${pair%%:*}
    dst=$to/${pair##*:}
    if [ "${1:-}" = --check ]; then
        if cmp -s "$src" "$dst"; then
            echo "vendor: $dst is $src of uplot $(node -p "require('./$from/package.json').version")"
        else
            echo "vendor: $dst differs from the npm package's $src (run scripts/vendor.sh)"
            status=1
        fi
    else
        mkdir -p "$to"
        cp "$src" "$dst"
        echo "vendor: copied $src to $dst"
    fi
done
exit $status
