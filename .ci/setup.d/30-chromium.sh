#!/usr/bin/env bash
# The browser test of `ger view` (host/tests/view.rs): Debian's Chromium,
# driven by playwright-core, which npm installs from tests/e2e's lock file.
# In CI the test fails rather than skips when these are missing.
set -euo pipefail
e2e="$(cd "$(dirname "$0")/../../tests/e2e" && pwd)"
if [ ! -x /usr/bin/chromium ] && command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
  apt-get install -y -qq chromium >/dev/null
fi
command -v npm >/dev/null || apt-get install -y -qq nodejs npm >/dev/null
(cd "$e2e" && npm ci --no-audit --no-fund --loglevel=error)
echo "chromium: $(/usr/bin/chromium --version 2>/dev/null || echo missing);" \
  "playwright-core $(node -p "require('$e2e/node_modules/playwright-core/package.json').version")"
