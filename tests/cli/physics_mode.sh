#!/bin/sh
# physics_mode.sh FLITTER DIR: which physics a run uses (README, "flitter-c
# and Flitter"). DIR holds petri.fl and its goldens: petri.simplified.state
# (PHYSICS.md, the default) and petri.upstream.state (Flitter 1.0.0b28 as
# published). petri.fl eases its appliers (ease=8), so the two differ.
#   - no option and --physics=documented give the documented dump;
#   - --physics=upstream and --physics upstream give Flitter's, on both
#     particle-pass routes;
#   - `%pragma physics :upstream` in the script gives Flitter's without
#     the option, and `%pragma physics :documented` overrides
#     --physics=upstream (the script's pragma wins, as with fps);
#   - an unknown pragma value is a warning naming it, and the option stays;
#   - bad option values are usage errors (exit 2) naming the option.
set -u
flitter=$1 dir=$2
opts="--frames 300 --dump-every 30"
work=$(mktemp -d) || exit 2
trap 'rm -rf "$work"' EXIT
doc="$dir/petri.simplified.state" up="$dir/petri.upstream.state"
cmp -s "$doc" "$up" && { echo "the two goldens are the same: the test cannot tell" >&2; exit 1; }
check() {   # check EXPECTED SCRIPT OPTIONS...
    expected=$1 script=$2
    shift 2
    # shellcheck disable=SC2086
    "$flitter" run $opts "$@" --dump-state "$script" >"$work/out" 2>"$work/err" ||
        { echo "$*: exit $?" >&2; cat "$work/err" >&2; exit 1; }
    cmp -s "$expected" "$work/out" || { echo "$script $*: state differs from $expected" >&2; exit 1; }
}
check "$doc" "$dir/petri.fl"
check "$doc" "$dir/petri.fl" --physics=documented
check "$up" "$dir/petri.fl" --physics=upstream
check "$up" "$dir/petri.fl" --physics upstream --particles literal
check "$up" "$dir/petri.fl" --physics upstream --particles fast --threads 2
{ echo '%pragma physics :upstream'; cat "$dir/petri.fl"; } >"$work/up.fl"
check "$up" "$work/up.fl"
{ echo "%pragma physics 'upstream'"; cat "$dir/petri.fl"; } >"$work/up2.fl"
check "$up" "$work/up2.fl"
{ echo '%pragma physics :documented'; cat "$dir/petri.fl"; } >"$work/doc.fl"
check "$doc" "$work/doc.fl" --physics=upstream
{ echo '%pragma physics :sideways'; cat "$dir/petri.fl"; } >"$work/bad.fl"
check "$up" "$work/bad.fl" --physics=upstream
grep -q "pragma physics" "$work/err" || { echo "no warning for :sideways" >&2; exit 1; }
for o in "--physics sideways" "--physics=" "--particles slow"; do
    # shellcheck disable=SC2086
    "$flitter" run $o --frames 1 "$dir/petri.fl" >/dev/null 2>"$work/err"
    rc=$?
    [ $rc -eq 2 ] || { echo "$o: expected exit 2, got $rc" >&2; exit 1; }
    grep -q "bad value.*--p" "$work/err" || { echo "$o: no message" >&2; cat "$work/err" >&2; exit 1; }
done
exit 0
