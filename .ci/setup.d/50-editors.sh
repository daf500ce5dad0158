#!/usr/bin/env bash
# `ger lsp` in real editors (host/tests/lsp.rs): Debian's Neovim, whose own
# LSP client the test drives headless, and in a terminal (tmux) for the
# README's picture (drawn by the Chromium of 30-chromium.sh); and the VS Code
# extension's packages, which npm installs from editors/vscode's lock file
# so the test can build the .vsix. In CI the tests fail rather than skip
# when these are missing.
set -euo pipefail
vscode="$(cd "$(dirname "$0")/../../editors/vscode" && pwd)"
if ! command -v nvim >/dev/null && command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
  apt-get install -y -qq neovim >/dev/null
fi
command -v tmux >/dev/null || apt-get install -y -qq tmux >/dev/null
command -v npm >/dev/null || apt-get install -y -qq nodejs npm >/dev/null
(cd "$vscode" && npm ci --no-audit --no-fund --loglevel=error)
echo "neovim: $(nvim --version 2>/dev/null | head -1 || echo missing); $(tmux -V);" \
  "vsce $(node -p "require('$vscode/node_modules/@vscode/vsce/package.json').version")"
