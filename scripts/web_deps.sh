#!/usr/bin/env bash
# Installs the npm packages of web/ (package-lock.json, exact versions): three.js and
# esbuild for the report's 3D view, the Foxglove and MCAP clients the tests use.
# Idempotent: does nothing when web/node_modules was installed from this lock file.
set -euo pipefail
cd "$(dirname "$0")/../web"
stamp=node_modules/.installed-package-lock.json
if cmp -s package-lock.json "$stamp"; then
  echo "web_deps: web/node_modules up to date"
  exit 0
fi
echo "web_deps: npm ci in web/"
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json "$stamp"
