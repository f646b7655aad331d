#!/bin/sh
# Where the linear coefficient a1 of the junction force-extension curve
# vanishes, for the disordered and the ordered 324-cell samples (the
# paper's Fig. 2: "near 3.86" for disordered tissue, p_hex for ordered).
#
# Per sample, quasistatically as an experiment would: relax at the first p0
# of the grid starting from the shipped sample (p0 3.65), then at every
# next p0 starting from the previous p0's relaxed mesh (tis-relax --p0).
# At every p0 the exact linear response a1 = -2/(g^T H^+ g) of all 972
# junctions (tis-forcelen --all --linear; one dense eigendecomposition per
# mesh, ~7 CPU s).  For the disordered samples the same p0 are also relaxed
# directly from the shipped sample ("direct"), a second route to a minimum:
# where the two disagree the answer depends on which minimum was found.
#
# Output in $OUT (default bench/out/disorder-a1):
#   SAMPLE-ROUTE-P0.mesh/.lin/.relax   relaxed mesh, linear table, report
#   a1-by-sample.tsv   per sample, route and p0: relax max force, nzero,
#                      nneg, quartiles of a1, fraction floppy (a1 = 0) and
#                      positive
#   a1-pooled.tsv      per set (disordered, ordered), route and p0: the
#                      quartiles of a1 over all junctions of all samples
#   crossings.tsv      per sample and pooled: where the median a1 reaches 0
#
# Cost: (10 samples x NP0 + 5 x NDIRECT) meshes x ~8 s; one process at a
# time (the machine is shared).  SUMMARY_ONLY=1 only redoes the tables.
set -eu
# Tables (tis(7)): '#' provenance lines, one line of column names, rows.
# ROWS selects the rows of tis-forcelen tables, however many were joined
# by cat (their first column is a number); BODY the rows of one table.
ROWS='$1 == $1 + 0'
BODY='/^#/ || !h++ { next } 1'
PROV="bench/disorder-a1.sh${*:+ $*}"

OUT=${OUT:-bench/out/disorder-a1}
SAMPLES_DIR=${SAMPLES_DIR:-samples}
DIS=${DIS:-"disordered-1 disordered-2 disordered-3 disordered-4 disordered-5"}
ORD=${ORD:-"ordered-11 ordered-12 ordered-13 ordered-14 ordered-15"}
P0_DIS=${P0_DIS:-"3.70 3.75 3.78 3.80 3.81 3.82 3.83 3.84 3.85 3.86 3.88 3.90"}
P0_ORD=${P0_ORD:-"3.70 3.72 3.74 3.76 3.78 3.80 3.82 3.84 3.86"}
P0_DIRECT=${P0_DIRECT:-"3.78 3.80 3.81 3.82 3.83 3.84 3.85 3.86 3.88"}
EULER_T=${EULER_T:-100}
FINE_N=${FINE_N:-4}
mkdir -p "$OUT"

# relax_lin SAMPLE ROUTE P0 FROM: relax FROM at P0 into SAMPLE-ROUTE-P0.mesh
# and measure every junction's a1.  Relaxation is overdamped dynamics first
# (tis-anneal at sigma 0 for EULER_T time units, T1s on), then tis-relax
# to polish the force balance.  Newton-CG alone, started from the previous
# p0's minimum, ran a junction to zero length on disordered-1 at p0 3.81
# ("no minimum at this topology", max force 1e-2) where 100 time units of
# gradient flow and then Newton reach 8e-13 with no T1: Newton steps in a
# non-convex landscape jump past the nearby minimum.  A missed tolerance is
# not fatal: the report (max force) is kept and the linear response says
# how many zero and negative modes the Hessian has there.
relax_lin() {
	b="$OUT/$1-$2-$3"
	if [ ! -s "$b.lin" ]; then
		tis-anneal --stage "0:$EULER_T" --relax 0 --settle 0 --p0 "$3" "$4" |
			tis-relax --p0 "$3" >"$b.mesh" 2>"$b.relax" || true
		tis-forcelen --all --linear --threads 1 "$b.mesh" >"$b.lin"
	fi
}

if [ "${SUMMARY_ONLY:-0}" != 1 ]; then
	for s in $DIS $ORD; do
		case $s in disordered*) grid=$P0_DIS ;; *) grid=$P0_ORD ;; esac
		prev="$SAMPLES_DIR/$s.mesh"
		for p in $grid; do
			relax_lin "$s" chain "$p" "$prev"
			prev="$OUT/$s-chain-$p.mesh"
		done
	done
	for s in $DIS; do
		for p in $P0_DIRECT; do
			relax_lin "$s" direct "$p" "$SAMPLES_DIR/$s.mesh"
		done
	done

	# Refinement: per sample, FINE_N more p0 evenly between the last grid
	# p0 with a negative median a1 and the next one, chained from the last
	# negative grid point ("fine").
	for s in $DIS $ORD; do
		case $s in disordered*) grid=$P0_DIS ;; *) grid=$P0_ORD ;; esac
		lo=
		for p in $grid; do
			med=$(awk "$ROWS"' { print $6 }' "$OUT/$s-chain-$p.lin" | sort -g |
				awk '{ v[n++] = $1 } END { print (n % 2 ? v[(n - 1) / 2] : (v[n / 2 - 1] + v[n / 2]) / 2) }')
			hi=$p
			if awk -v m="$med" 'BEGIN { exit !(m < 0) }'; then lo=$p; else break; fi
		done
		[ -n "$lo" ] && [ "$hi" != "$lo" ] || continue
		prev="$OUT/$s-chain-$lo.mesh"
		k=1
		while [ "$k" -le "$FINE_N" ]; do
			p=$(awk -v lo="$lo" -v hi="$hi" -v k="$k" -v n="$FINE_N" 'BEGIN { printf "%.4f", lo + k * (hi - lo) / (n + 1) }')
			relax_lin "$s" fine "$p" "$prev"
			prev="$OUT/$s-fine-$p.mesh"
			k=$((k + 1))
		done
	done
fi

# Quartiles with linear interpolation between order statistics.
QAWK='function q(p,  h, i) { h = (n - 1) * p; i = int(h); return i + 1 < n ? v[i] + (h - i) * (v[i + 1] - v[i]) : v[i] }'

# Per sample, route and p0.
{
	printf '# %s\nsample\troute\tp0\tmaxforce\tnzero\tnneg\tn\ta1_q1\ta1_med\ta1_q3\tfloppy\tpositive\tT1s\n' "$PROV"
	for f in "$OUT"/*.lin; do
		b=${f%.lin}
		name=${b##*/}
		p=${name##*-}
		rest=${name%-*}
		route=${rest##*-}
		s=${rest%-*}
		mf=$(sed -n 's/.*max force \([^,]*\),.*/\1/p' "$b.relax" | head -1)
		t1=$(sed -n 's/^history tis-anneal.* \([0-9]*\) T1s.*/\1/p' "$b.mesh" | tail -1)
		awk "$ROWS"' { print $6, $7, $8 }' "$f" | sort -g | awk -v s="$s" -v r="$route" -v p="$p" -v mf="${mf:-NA}" -v t1="${t1:-NA}" "$QAWK"'
			{ v[n++] = $1; fl += $1 == 0; po += $1 > 0; nz = $2; ng = $3 }
			END { printf "%s\t%s\t%s\t%s\t%d\t%d\t%d\t%.6g\t%.6g\t%.6g\t%.4f\t%.4f\t%s\n",
			      s, r, p, mf, nz, ng, n, q(0.25), q(0.5), q(0.75), fl / n, po / n, t1 }'
	done | sort -k2,2 -k1,1V -k3,3g
} >"$OUT/a1-by-sample.tsv"

# Pooled over the samples of a set: every junction of every sample.
{
	printf '# %s\nset\troute\tp0\tnsamples\tn\ta1_q1\ta1_med\ta1_q3\tfloppy\tpositive\tmaxforce_max\tnneg_max\n' "$PROV"
	for set in disordered ordered; do
		for route in chain direct; do
			for p in $(ls "$OUT" | sed -n "s/^$set-[0-9]*-$route-\(.*\)\.lin$/\1/p" | sort -gu); do
				ns=$(ls "$OUT" | grep -c "^$set-[0-9]*-$route-$p\.lin$")
				extra=$(awk -v set="$set" -v r="$route" -v p="$p" -F '\t' '
					index($1, set) == 1 && $2 == r && $3 == p {
						if ($4 + 0 > mf) mf = $4 + 0; if ($6 > ng) ng = $6 }
					END { printf "%.3g\t%d", mf, ng }' "$OUT/a1-by-sample.tsv")
				cat "$OUT/$set"-[0-9]*-"$route-$p.lin" | awk "$ROWS"' { print $6 }' | sort -g |
					awk -v set="$set" -v r="$route" -v p="$p" -v ns="$ns" -v extra="$extra" "$QAWK"'
					{ v[n++] = $1; fl += $1 == 0; po += $1 > 0 }
					END { printf "%s\t%s\t%s\t%d\t%d\t%.6g\t%.6g\t%.6g\t%.4f\t%.4f\t%s\n",
					      set, r, p, ns, n, q(0.25), q(0.5), q(0.75), fl / n, po / n, extra }'
			done
		done
	done
} >"$OUT/a1-pooled.tsv"

# Zero crossing of the median: the first p0 at which the median is >= 0
# after a negative one.  Two estimates: linear interpolation between the
# bracketing grid points (biased upward when the median jumps to exactly
# 0 because most junctions turned floppy), and linear extrapolation of the
# last two negative medians (a1 is nearly linear in p0 near the crossing
# on the honeycomb), clipped to the bracket.  Meshes whose relaxation
# stopped above max force 1e-4 (a junction ran to zero length: not a
# minimum) are left out; below that, a missed tolerance is the non-isolated
# minimum of a floppy tissue and counts.
CROSS='
	function out() {
		if (!found) { printf "%s\t%s\tNA\tNA\tNA\tNA\n", key, route; return }
		printf "%s\t%s\t%s\t%s\t%.4f\t%.4f\n", key, route, plo, phi, pint, pext
	}
	{ k = $1 "\t" $2 }
	k != cur { if (cur != "") out(); cur = k; key = $1; route = $2; found = 0; np = 0 }
	!found && $(fcol) + 0 <= 1e-4 {
		p = $3 + 0; m = $(col) + 0
		if (m < 0) { pp = plast; mp = mlast; plast = p; mlast = m; np++ }
		else if (np > 0) {
			found = 1; plo = plast; phi = p
			pint = plast - mlast * (p - plast) / (m - mlast)
			pext = np > 1 ? plast - mlast * (plast - pp) / (mlast - mp) : phi
			if (pext > phi) pext = phi
			if (pext < plo) pext = plo
		}
	}
	END { if (cur != "") out() }'
{
	printf '# %s\nsample_or_set\troute\tp0_lo\tp0_hi\tp0_interp\tp0_extrap\n' "$PROV"
	# chain and fine are one quasistatic route
	awk -F '\t' -v OFS='\t' "$BODY"' { if ($2 == "fine") $2 = "chain"; print }' "$OUT/a1-by-sample.tsv" |
		sort -t "$(printf '\t')" -k1,1V -k2,2 -k3,3g |
		awk -F '\t' -v col=9 -v fcol=4 "$CROSS"
	awk -F '\t' "$BODY" "$OUT/a1-pooled.tsv" | awk -F '\t' -v col=7 -v fcol=11 "$CROSS"
} >"$OUT/crossings.tsv"
cat "$OUT/crossings.tsv"
