#!/usr/bin/env bash
# The README's test command: installs dependencies, builds everything, runs every test, and checks
# that the artefacts a user needs exist. Fails when anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/install-deps.sh
python3 -c 'import numpy' 2>/dev/null || python3 -m pip install --quiet numpy || true
bash scripts/build.sh
ctest --test-dir build --output-on-failure --timeout 900
# Every parser under libFuzzer + ASan + UBSan, a few seconds each (docs/SECURITY.md "Fuzzing");
# fails the run on a crash, a hang or running out of memory.
bash scripts/fuzz.sh "${ARMADILLO_FUZZ_SECONDS:-3}"
bash scripts/check-artefacts.sh
echo "test.sh: finished in $(( $(date +%s) - start )) s"
