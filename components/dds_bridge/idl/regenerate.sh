#!/usr/bin/env bash
# Regenerates the Fast DDS type support of envelope.idl (envelope.{h,cxx},
# envelopePubSubTypes.{h,cxx}) in this folder. Needs fastddsgen (Debian: fastddsgen 2.3.0,
# matching Fast DDS 2.9.1). The generated files are kept in the repository, so a build
# does not need Java; run this after editing envelope.idl and commit the result.
set -euo pipefail
cd "$(dirname "$0")"
fastddsgen -replace -d . envelope.idl
