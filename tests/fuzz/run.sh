#!/usr/bin/env bash
# run.sh BUILD_DIR SECONDS [TARGET...]: run each libFuzzer target of
# BUILD_DIR (built with -Dfuzz=true, ASan+UBSan) for SECONDS on a scratch
# copy of its seed corpus, with tests/fuzz/flitter.dict. Exits non-zero on
# any finding (crash, sanitizer report, leak, timeout, out-of-memory); the
# reproducer and the log are kept in $FUZZ_ARTIFACTS (default
# BUILD_DIR/fuzz-artifacts). Prints one line per target with its executions.
# Seeds: scripts from tests/golden, tests/lang, tests/errors, samples and
# tests/cli (for `script`, `repl` and `templates`), tests/fuzz/corpus/TARGET
# for the others.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "$1" && pwd) seconds=$2
shift 2
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(script statefile repl define templates)
artifacts=${FUZZ_ARTIFACTS:-$build/fuzz-artifacts}
mkdir -p "$artifacts"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/tests/lsan.supp}
status=0
for t in "${targets[@]}"; do
    exe=$build/tests/fuzz/fuzz_$t
    [ -x "$exe" ] || { echo "fuzz $t: $exe not built" >&2; status=1; continue; }
    # scratch on tmpfs when there is one: the state target saves (and
    # fsyncs) a file per accepted input
    shm=/dev/shm
    [ -d $shm ] && [ -w $shm ] || shm=${TMPDIR:-/tmp}
    work=$(mktemp -d -p "$shm")
    mkdir "$work/corpus" "$work/tmp"
    case $t in
        script|repl|templates)
            for d in tests/golden tests/lang tests/errors samples tests/cli; do
                for f in "$root/$d"/*.fl; do
                    # not the seeds that build 2^24-element vectors on
                    # purpose: slow, and the REPL prints every element
                    case $f in */vector_too_long.fl) continue ;; esac
                    [ "$(stat -c %s "$f")" -le 4096 ] && cp "$f" "$work/corpus/${d##*/}-${f##*/}"
                done
            done
            [ "$t" = repl ] && cp "$root"/tests/fuzz/corpus/repl/* "$work/corpus/" ;;
        *)  cp "$root"/tests/fuzz/corpus/"$t"/* "$work/corpus/" ;;
    esac
    # the targets run scripts that may read files: run them in an empty
    # directory with no input, scratch files in their own TMPDIR
    (cd "$work/tmp" && TMPDIR="$work/tmp" "$exe" "$work/corpus" \
        -dict="$here/flitter.dict" -max_total_time="$seconds" -max_len=4096 \
        -timeout=20 -rss_limit_mb=4096 -malloc_limit_mb=4096 -print_final_stats=1 \
        -artifact_prefix="$artifacts/$t-" </dev/null >"$work/log" 2>&1)
    rc=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' "$work/log" | tail -1)
    if [ $rc -ne 0 ]; then
        cp "$work/log" "$artifacts/$t.log"
        echo "fuzz $t: FINDING (exit $rc) after ${runs:-?} executions; log $artifacts/$t.log" >&2
        grep -m 5 -E "ERROR|runtime error|SUMMARY" "$work/log" >&2
        status=1
    else
        echo "fuzz $t: ${runs:-?} executions in ${seconds}s, ${cov:-cov: ?}, no findings"
    fi
    rm -rf "$work"
done
exit $status
