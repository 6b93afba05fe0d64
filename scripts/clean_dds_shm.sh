#!/usr/bin/env bash
# Removes Fast DDS's shared-memory files (/dev/shm/fastrtps_*, sem.fastrtps_*,
# fast_datasharing_*) that no process has open: those a SIGKILLed process left behind
# (the fault tests kill robots). A port file left with its mutex taken can keep the next
# team from discovering itself (eProsima/Fast-DDS issues 1144, 5053). Files still in use
# (another team running) are kept (fuser). Prints how many it removed.
set -euo pipefail
removed=0
shopt -s nullglob
for f in /dev/shm/fastrtps_* /dev/shm/sem.fastrtps_* /dev/shm/fast_datasharing_*; do
  if ! fuser -s "$f" 2>/dev/null; then
    rm -f "$f" && removed=$((removed + 1))
  fi
done
echo "clean_dds_shm: removed $removed unused Fast DDS shared-memory files"
