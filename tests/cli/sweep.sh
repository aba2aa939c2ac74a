#!/usr/bin/env bash
# sweep.sh FLITTER SCRIPT: `flitter sweep` lists 2 strengths x 2 values x 2
# runs = 8 jobs; GNU parallel (-j2) runs them; each job's final.state is
# the --dump-state of the same `flitter run`; runs 0 and 1 differ (the run
# number seeds !random); a hostile value (a quote and $(...)) reaches the
# script and the manifest unchanged and runs nothing; a finished job run
# again returns at once, changing nothing; --collect prints the CSV;
# --slurm writes a job-array script whose task 3 runs job 3.
set -uo pipefail
flitter=$1 script=$2
command -v parallel >/dev/null || { echo "GNU parallel not installed: skipped"; exit 77; }
dir=$(mktemp -d) || exit 2
trap 'rm -rf "$dir"' EXIT
out=$dir/out
fail() { echo "FAIL: $*" >&2; exit 1; }
hostile="it's \$(touch $dir/pwned) \`touch $dir/pwned2\`"

"$flitter" sweep "$script" -D strength=50,200 -D "tag=plain,$hostile" --runs 2 --frames 30 \
    --out "$out" >"$dir/jobs" || fail "sweep listing exited $?"
[ "$(wc -l <"$dir/jobs")" -eq 8 ] || fail "expected 8 job lines, got $(wc -l <"$dir/jobs")"
parallel --will-cite -j2 --joblog "$dir/joblog" <"$dir/jobs" || fail "parallel exited $?"
[ ! -e "$dir/pwned" ] && [ ! -e "$dir/pwned2" ] || fail "a value was run by the shell"
# joblog: 8 rows, column 7 (Exitval) all 0
[ "$(awk 'NR > 1 && $7 == 0' "$dir/joblog" | wc -l)" -eq 8 ] || { cat "$dir/joblog" >&2; fail "joblog"; }

# job 3 = strength 50, the hostile tag, run 1
grep -qxF "param tag $hostile" "$out/job-0003/manifest" || { cat "$out/job-0003/manifest" >&2; fail "manifest value"; }
"$flitter" run --frames 30 -D strength=50 -D "tag=$hostile" -D run=1 --dump-state "$script" \
    >"$dir/want3" 2>/dev/null || fail "direct run"
cmp -s "$dir/want3" "$out/job-0003/final.state" || fail "job 3's final.state differs from the same flitter run"
cmp -s "$out/job-0002/final.state" "$out/job-0003/final.state" && fail "runs 0 and 1 gave the same state"
[ -s "$out/job-0003/trace.csv" ] && [ -s "$out/job-0003/run.state" ] || fail "trace or state missing"
head -1 "$out/job-0003/trace.csv" | grep -qx 'frame,time,system,id,kind,x,y,vx,vy' || fail "trace header"

# a finished job returns at once and leaves its files alone
cp "$out/job-0003/manifest" "$dir/m3"
line4=$(sed -n 4p "$dir/jobs")
bash -c "$line4" 2>"$dir/again" || fail "re-run exited $?"
grep -q "already finished" "$dir/again" || fail "re-run did not say it was finished"
cmp -s "$dir/m3" "$out/job-0003/manifest" || fail "re-run changed the manifest"

# the CSV, wall times left out (column 7)
"$flitter" sweep --collect "$out" >"$dir/csv" || fail "collect exited $?"
cat >"$dir/want.csv" <<'CSV'
job,strength,tag,run,seed,exit
0,50,plain,0,0,0
1,50,plain,1,1,0
2,50,HOSTILE,0,0,0
3,50,HOSTILE,1,1,0
4,200,plain,0,0,0
5,200,plain,1,1,0
6,200,HOSTILE,0,0,0
7,200,HOSTILE,1,1,0
CSV
# the hostile value has no comma or quote that CSV must escape but "'": it
# is written unquoted
cut -d, -f1-6 "$dir/csv" | sed "s/$(sed 's/[][\\/.*^$]/\\&/g' <<<"$hostile")/HOSTILE/" >"$dir/csv6"
diff -u "$dir/want.csv" "$dir/csv6" >&2 || fail "collected CSV"
awk -F, 'NR > 1 && $7 !~ /^[0-9]+\.[0-9][0-9][0-9]$/ {bad = 1} END {exit bad}' "$dir/csv" || fail "wall_seconds column"

# a value with a comma and a quote is quoted in the CSV (RFC 4180)
"$flitter" sweep --job 0 --run 0 --out "$dir/q" --frames 1 -D 'tag=x' "$script" 2>/dev/null || fail "single job"
sed -i 's/^param tag x$/param tag a,"b"/' "$dir/q/job-0000/manifest"
"$flitter" sweep --collect "$dir/q" | sed -n 2p | cut -d, -f1-3 | grep -qx '0,"a,""b"""' || fail "CSV quoting"

# Slurm: the job array script, task 3 run by hand as sbatch would
"$flitter" sweep "$script" -D strength=50,200 -D "tag=plain,$hostile" --runs 2 --frames 30 \
    --out "$dir/slurm" --slurm >"$dir/sb" || fail "--slurm exited $?"
grep -qx '#SBATCH --array=0-7' "$dir/slurm/sweep.sbatch" || fail "array line"
SLURM_ARRAY_TASK_ID=3 sh "$dir/slurm/sweep.sbatch" 2>/dev/null || fail "task 3"
cmp -s "$dir/want3" "$dir/slurm/job-0003/final.state" || fail "slurm task 3's final.state"
[ ! -e "$dir/pwned" ] && [ ! -e "$dir/pwned2" ] || fail "a value was run by the shell (slurm)"

# signed, suffixed and empty values reach the script as Flitter reads them
# (issue 59: -200 and 1 once ran as the same string), the manifest records
# what the script received and the CSV shows the numbers
"$flitter" sweep "$script" -D strength=-200,1,2k -D tag= --frames 5 --out "$dir/v" >"$dir/vjobs" ||
    fail "signed sweep listing exited $?"
bash "$dir/vjobs" 2>/dev/null || fail "signed sweep jobs"
grep -qx 'value strength -200' "$dir/v/job-0000/manifest" || fail "manifest value -200"
grep -qx 'value strength 2000' "$dir/v/job-0002/manifest" || fail "manifest value 2k"
grep -qx 'value tag ""' "$dir/v/job-0000/manifest" || fail "manifest value of an empty text"
cmp -s "$dir/v/job-0000/final.state" "$dir/v/job-0001/final.state" && fail "strength -200 ran as 1"
"$flitter" run --frames 5 -D strength=-200 -D tag= -D run=0 --dump-state "$script" 2>/dev/null |
    cmp -s - "$dir/v/job-0000/final.state" || fail "job 0 differs from flitter run -D strength=-200"
"$flitter" sweep --collect "$dir/v" | cut -d, -f1-3 | tr '\n' ' ' |
    grep -qx 'job,strength,tag 0,-200, 1,1, 2,2000, ' || fail "CSV of received values"

# a script that does not read `run` gets no seed from the run number
printf '!physics state=:p dimensions=1\n    !particle id=1 position=0 velocity=v\n' >"$dir/norun.fl"
"$flitter" sweep "$dir/norun.fl" -D v=1 --runs 2 --frames 2 --out "$dir/n" >"$dir/njobs" || fail "norun listing"
bash "$dir/njobs" 2>/dev/null || fail "norun jobs"
"$flitter" sweep --collect "$dir/n" | cut -d, -f1-4 | tr '\n' ' ' | grep -qx 'job,v,run,seed 0,1,0, 1,1,1, ' ||
    fail "seed of a script without run: $("$flitter" sweep --collect "$dir/n")"

# hostile folder names (issue 60): a line break never reaches a job line or
# the batch script, and a #SBATCH line gets no blank, quote or newline (all
# refused before anything is made); a % is doubled for Slurm's patterns
nl=$(printf 'x\ny')
for out in "$dir/$nl" "$dir/a b" "$dir/q'x"; do
    "$flitter" sweep "$script" -D strength=1 --frames 1 --out "$out" --slurm >/dev/null 2>"$dir/err"
    [ $? -eq 2 ] && grep -q "cannot carry\|line break" "$dir/err" || fail "--slurm --out '$out' accepted"
    [ ! -e "$out" ] || fail "--slurm --out '$out' made the folder"
done
"$flitter" sweep "$script" -D strength=1 --frames 1 --out "$dir/$nl" >/dev/null 2>"$dir/err"
[ $? -eq 2 ] && grep -q "line break in --out" "$dir/err" || fail "a job line with a line break"
"$flitter" sweep "$script" -D strength=1 --frames 1 --out "$dir/p%j" --slurm >/dev/null || fail "--out p%j"
grep -qxF "#SBATCH --output=$dir/p%%j/slurm-%A_%a.out" "$dir/p%j/sweep.sbatch" || fail "% not doubled"

# --collect reads manifests only as regular files of bounded size: a FIFO
# (which would hang it), a link to /dev/zero (read without end), a missing
# and a damaged one are each named, the CSV keeps the good rows, exit 1
cp -r "$dir/n" "$dir/c"
mkdir "$dir/c/job-0002" "$dir/c/job-0003" "$dir/c/job-0004"
mkfifo "$dir/c/job-0002/manifest" && ln -s /dev/zero "$dir/c/job-0003/manifest" &&
    printf 'job 4\n' >"$dir/c/job-0004/manifest" && mkdir "$dir/c/job-0005" || fail "setting up --collect"
timeout 10 "$flitter" sweep --collect "$dir/c" >"$dir/ccsv" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] || fail "--collect of damaged manifests: exit $rc"
[ "$(wc -l <"$dir/ccsv")" -eq 3 ] || fail "--collect: not the 2 good rows: $(cat "$dir/ccsv")"
for w in "job-0002/manifest: not a regular file" "job-0003/manifest: a symbolic link" \
         "job-0004/manifest: damaged" "job-0005/manifest: missing" "4 of 6 jobs have no readable manifest"; do
    grep -q "$w" "$dir/err" || fail "--collect did not say '$w': $(cat "$dir/err")"
done
# a manifest whose fields are not what a job writes is damaged too: each
# named with its reason, exit 1 (they were once printed as CSV rows, exit 0)
good=$(ls "$dir/n" | head -n 1)
for edit in 's/^exit .*/exit banana/:exit status' 's/^exit .*/exit -3/:exit status' \
            's/^exit .*/exit 99999999999999999999/:exit status' 's/^wall_seconds .*/wall_seconds nan/:wall_seconds' \
            's/^seed .*/seed zz/:seed' 's/^run .*/run -x/:run' 's/^exit \(.*\)/exit \1\nexit 1/:two' \
            's/^job .*/job 77/:not that of its folder' 's/^frames /bogus /:unknown line'; do
    rm -rf "$dir/d" && mkdir "$dir/d" && cp -r "$dir/n/$good" "$dir/d/" || fail "setting up a damaged manifest"
    sed -i "${edit%%:*}" "$dir/d/$good/manifest"
    "$flitter" sweep --collect "$dir/d" >/dev/null 2>"$dir/err"
    rc=$?
    [ $rc -eq 1 ] && grep -q "manifest: damaged (.*${edit#*:}" "$dir/err" ||
        fail "--collect of a manifest edited by '${edit%%:*}': exit $rc, $(cat "$dir/err")"
done
# job counts beyond the bound are refused, never wrapped around
"$flitter" sweep "$script" -D strength=1,2 --runs 9223372036854775807 --frames 1 --out "$dir/huge" \
    >/dev/null 2>"$dir/err"
[ $? -eq 2 ] && grep -q "more than 1000000 jobs" "$dir/err" || fail "an overflowing job count: $(cat "$dir/err")"
[ ! -e "$dir/huge" ] || fail "an overflowing job count made its folder"

# a job runs alone in its folder and its child dies with it (issue 60):
# a second start of a running job leaves it be (exit 1, its log and files
# untouched); a job killed with SIGKILL takes its `flitter run` with it, and
# the job run again afterwards finishes, its results written under names of
# its own and the killed run's temporary files removed
"$flitter" sweep --job 0 --run 0 --out "$dir/k" --frames 10000000 -D v=1 "$dir/norun.fl" 2>/dev/null &
jp=$!
i=0; while [ ! -s "$dir/k/job-0000/trace.csv" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
child=$(pgrep -P $jp)
[ -n "$child" ] || fail "no child of the running job"
[ -e "$dir/k/job-0000/final.state.$jp.tmp" ] || fail "the running job's output is not under a name of its own"
"$flitter" sweep --job 0 --run 0 --out "$dir/k" --frames 3 -D v=1 "$dir/norun.fl" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "being run by another process" "$dir/err" || fail "a second start: $(cat "$dir/err")"
kill -0 "$child" 2>/dev/null || fail "the second start ended the first's run"
kill -9 $jp
wait $jp 2>/dev/null
i=0
while ps -o stat= -p "$child" 2>/dev/null | grep -qv Z && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
ps -o stat= -p "$child" 2>/dev/null | grep -qv Z && fail "the killed job's child runs on"
"$flitter" sweep --job 0 --run 0 --out "$dir/k" --frames 3 -D v=1 "$dir/norun.fl" 2>"$dir/err" ||
    fail "the job run again: $(cat "$dir/err")"
grep -qx 'exit 0' "$dir/k/job-0000/manifest" || fail "the job run again is not recorded finished"
[ -s "$dir/k/job-0000/final.state" ] || fail "the job run again has no final.state"
ls "$dir/k/job-0000" | grep '\.tmp$' && fail "temporary files left in the job's folder"

# bad usage: exit 2 with a message
"$flitter" sweep "$script" -D 'bad name=1' --frames 1 --out "$dir/x" 2>"$dir/err"
[ $? -eq 2 ] && grep -q "bad define" "$dir/err" || fail "bad define accepted"
"$flitter" sweep "$script" -D run=1,2 --frames 1 --out "$dir/x" 2>/dev/null
[ $? -eq 2 ] || fail "-D run accepted"
echo "sweep: all checks passed"
