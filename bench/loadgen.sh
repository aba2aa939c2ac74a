#!/bin/sh
# bench/loadgen.sh DIR: write the generated load-time benchmark scripts of
# issue 28 item 4 (and the flat scripts its tests use) into DIR:
#   bindings40k.fl  one `let` with 40,000 bindings (continuation lines),
#                   each but the first depending on the one before
#   names50k.fl     50,000 distinct unbound names, one node each
#   lets10k.fl      10,000 top-level `let` lines, then a node using them
#   funcs10k.fl     10,000 top-level `func`s, then a node calling them
# bench/load.sh times them; tests/cli/flat_scripts.sh runs the flat ones.
set -eu
dir=${1:?usage: loadgen.sh DIR}
mkdir -p "$dir"
awk 'BEGIN {
    print "let x0=time";
    for (i = 1; i < 40000; i++) printf "    x%d=x%d*0.5+%d\n", i, i - 1, i;
    print "!n v=x39999";
}' > "$dir/bindings40k.fl"
awk 'BEGIN { for (i = 0; i < 50000; i++) printf "!n v=u%d\n", i; }' > "$dir/names50k.fl"
awk 'BEGIN {
    print "let x0=time";
    for (i = 1; i < 10000; i++) printf "let x%d=x%d+%d\n", i, i - 1, i % 7;
    print "!n v=x9999";
}' > "$dir/lets10k.fl"
awk 'BEGIN {
    for (i = 0; i < 10000; i++) printf "func f%d(x)\n    x*%d+time\n", i, i % 5;
    printf "!n";
    for (i = 0; i < 10000; i += 1111) printf " v%d=f%d(%d)", i, i, i;
    print "";
}' > "$dir/funcs10k.fl"
