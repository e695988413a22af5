#!/bin/sh
# Installs the pinned validator packages into the directory given, once: again only when the
# lock file changes.
set -eu
cd "$1"
if [ -f node_modules/.installed-lock.json ] && cmp -s package-lock.json node_modules/.installed-lock.json; then
  exit 0
fi
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json node_modules/.installed-lock.json
