#!/bin/sh
# Run a sweep with GNU parallel.  Copy this script and edit it to taste.
#
#   parallel.sh DIR [PARALLEL OPTIONS...]
#
# One job per row of DIR/params.tsv, each `sweep-row DIR N`.  The joblog
# (DIR/joblog) and --resume skip rows that parallel has already run; rows
# with a result file are skipped by sweep-row itself, so a sweep killed
# in any way (or moved from one engine to another) resumes where it was.
# Use --resume-failed in the options to retry failed rows.
#
# Several machines: DIR must be on a file system they share, at the same
# path, with the tis programs and these scripts on their PATH:
#
#   parallel.sh /shared/sweep --sshlogin 8/node1,8/node2 --env PATH
#
# The rows go to DIR/results/N.tsv; sweep-reduce DIR joins them.  Each
# job computes on one core (the programs' --threads default is
# OMP_NUM_THREADS), unless OMP_NUM_THREADS is set: the jobs are the
# parallelism.
set -eu
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
[ $# -ge 1 ] || { echo "usage: parallel.sh DIR [PARALLEL OPTIONS...]" >&2; exit 2; }
dir=$1
shift
n=$(sweep-count "$dir")
seq 1 "$n" | parallel --joblog "$dir/joblog" --resume "$@" sweep-row "$dir" {} >/dev/null
