#!/usr/bin/env bash
# The shared objects made of the library's objects (libflitter.so, the
# Python module) read their thread-local variables at fixed offsets from
# the thread pointer (initial-exec, lib/core/mem.h FL_THREAD_LOCAL), not
# through a call of __tls_get_addr on every pool allocation.
# usage: tls.sh SHARED_OBJECT...
set -uo pipefail
[ $# -gt 0 ] || { echo "usage: tls.sh SHARED_OBJECT..."; exit 2; }
for so in "$@"; do
    undefined=$(nm -D --undefined-only "$so") || { echo "cannot read $so"; exit 1; }
    if grep -qw '__tls_get_addr' <<<"$undefined"; then
        echo "$so calls __tls_get_addr: a thread-local variable without FL_THREAD_LOCAL"
        exit 1
    fi
    echo "$so: no __tls_get_addr"
done
