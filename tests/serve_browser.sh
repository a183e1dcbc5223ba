#!/usr/bin/env bash
# softface serve in a real browser: start `softface serve` on
# tests/serve_cube.prm (any free port), drive its page in headless Chromium
# (web/test/serve_browser.mjs: load, 10 slider moves each waited for until the
# face is redrawn, 7 bad requests answered with errors while the server
# serves on, a screenshot), then stop the server with Ctrl-C (SIGINT): it
# must exit 0.
#
#   tests/serve_browser.sh SOFTFACE SCENE.prm WORK_DIR
set -u
softface=$1 scene=$2 work=$3
web=$(cd "$(dirname "$0")/../web" && pwd)
mkdir -p "$work" && cd "$work" || exit 1
for need in "$web/node_modules/three" "$web/node_modules/playwright-core"; do
  [ -e "$need" ] || { echo "serve_browser: $need is missing: run 'npm ci' in $web (./test.sh does)"; exit 1; }
done
command -v node > /dev/null || { echo "serve_browser: no node (Debian: nodejs)"; exit 1; }
[ -x "${CHROMIUM:-/usr/bin/chromium}" ] || { echo "serve_browser: no chromium (Debian: chromium; ./test.sh installs it)"; exit 1; }

"$softface" serve "$scene" > serve.log 2>&1 &
pid=$!
url=
for _ in $(seq 1200); do
  url=$(grep -o 'http://[0-9.]*:[0-9]*/' serve.log | head -n 1)
  [ -n "$url" ] && break
  kill -0 "$pid" 2> /dev/null || { echo "serve_browser: softface serve ended:"; cat serve.log; exit 1; }
  sleep 0.1
done
[ -n "$url" ] || { echo "serve_browser: no URL after 120 s:"; cat serve.log; kill "$pid"; exit 1; }
echo "serve_browser: $url"
node "$web/test/serve_browser.mjs" "$url" "$work/serve_browser.png" 10
rc=$?
kill -INT "$pid"
wait "$pid"
serve_rc=$?
cat serve.log
if [ "$serve_rc" -ne 0 ] || ! grep -q "softface serve: stopped" serve.log; then
  echo "serve_browser: softface serve did not stop cleanly on SIGINT (exit $serve_rc)"
  rc=1
fi
exit "$rc"
