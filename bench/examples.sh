#!/bin/sh
# bench/examples.sh --examples DIR [--examples DIR]... [--frames N] [--reps R] [BUILD_DIR]: the
# evaluator on Flitter's own examples against Flitter (FLITTER_REF); see
# bench/examples.py, which it runs.
exec python3 "$(dirname "$0")/examples.py" "$@"
