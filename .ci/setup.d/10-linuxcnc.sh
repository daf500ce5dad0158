#!/usr/bin/env bash
# LinuxCNC's standalone interpreter, rs274: the trusted peer the differential
# tests compare ger's geometry with (they fail in CI if it is missing).
set -euo pipefail
command -v rs274 >/dev/null || apt-get install -y -qq linuxcnc-uspace >/dev/null
rs274 -h >/dev/null 2>&1 || true
echo "rs274: $(command -v rs274)"
