#!/bin/sh
# docs/parameters.md is the output of `scancrew components --markdown` (each component's
# read_config() run over ParamReader::describing()). Fails, saying how to regenerate it, when
# the page and the registry differ. Usage: check_parameters_doc.sh SCANCREW_BINARY PAGE
set -u
bin=$1
page=$2
out=$(mktemp) || exit 1
trap 'rm -f "$out"' EXIT
"$bin" components --markdown >"$out" || { echo "scancrew components --markdown failed"; exit 1; }
if ! diff -u "$page" "$out"; then
  echo "docs/parameters.md is stale (the diff above: page -> registry). Regenerate it from the"
  echo "repository root with:"
  echo "  build/release/cli/scancrew components --markdown > docs/parameters.md"
  exit 1
fi
echo "docs/parameters.md is current"
