#!/usr/bin/env bash
# Builds the LMS200 framer fuzz target with clang's libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer straight from the pure sources and runs it for <seconds>.
# Exits non-zero when the fuzzer finds a crash (the reproducer is left in the work dir).
#
#   robot_server/laser/run_fuzzer.sh 60 [work_dir]
set -euo pipefail
seconds="${1:?usage: run_fuzzer.sh <seconds> [work_dir]}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "${here}/../.." && pwd)"
work="${2:-$(mktemp -d)}"
cxx="${CXX_FUZZ:-clang++}"
mkdir -p "${work}/corpus"
cp -n "${here}"/fuzz_corpus/* "${work}/corpus/" 2>/dev/null || true
"${cxx}" -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"${root}" \
  "${here}/lms200_framer_fuzzer.cc" "${here}/lms200_framer.cc" "${here}/lms200_crc.cc" \
  "${here}/lms200_telegrams.cc" -o "${work}/lms200_framer_fuzzer"
cd "${work}"
./lms200_framer_fuzzer -max_total_time="${seconds}" -max_len=4096 -timeout=10 \
  -print_final_stats=1 corpus
