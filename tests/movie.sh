#!/bin/sh
# tis-movie: an MP4 and a GIF that ffprobe reads with one frame per mesh
# and the duration frames/fps; the frames themselves (--format ppm): the
# marked junction in green, tension signs in red and blue on honeycombs
# whose tension is known (4 (P_hex - p0)), the same pixels from a .pvd as
# from the stream it was made from; clean failures on bad input, without
# ffmpeg and when ffmpeg fails.  The encoder tests skip without ffmpeg.
. "$(dirname "$0")/lib.sh"
plan 26

tis-hex 4 4 | tis-relax --quiet --p0 3.7224194 >"$T/phex.mesh"
tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 40 --every 4 "$T/phex.mesh" >"$T/frames.mesh"
nf=$(grep -c '^tismesh 1' "$T/frames.mesh")
ok "the run wrote its frames: the start, ten and the final ($nf)" test "$nf" -eq 12

# a PPM stream of equal frames: its header's bytes, a frame's pixel bytes
# and width; frames: how many; pixels: of one colour ("R G B") in frame K,
# in the picture of the box only (above the colour bar's strip of 34
# rows); od prints one pixel per line
geom() { head -c 64 "$1" | awk 'NR == 2 { w = $1; n = $1 * $2 * 3; r = $2 - 34 } NR <= 3 { h += length($0) + 1 } END { print h, n, w, r }'; }
frames() { geom "$1" >"$T/geom"; read -r hd nb w r <"$T/geom"; s=$(wc -c <"$1"); [ $((s % (hd + nb))) -eq 0 ] && echo $((s / (hd + nb))); }
pixels() { # FILE K R G B
	geom "$1" >"$T/geom"; read -r hd nb w r <"$T/geom"
	tail -c +$((1 + $2 * (hd + nb) + hd)) "$1" | head -c $((3 * w * r)) | od -An -v -tu1 -w3 |
		awk -v c="$3 $4 $5" '{ $1 = $1 } $0 == c { n++ } END { print n + 0 }'
}
tis-movie --format ppm -o - "$T/frames.mesh" >"$T/f.ppm"
ok "--format ppm: one image per mesh" test "$(frames "$T/f.ppm")" -eq "$nf"
ok "every frame 496 x 458 (the box 480 wide, margins, the bar; even)" \
	test "$(grep -ac '^496 458$' "$T/f.ppm")" -eq "$nf"
ok "the active junction is marked in green" test "$(pixels "$T/f.ppm" 3 0 166 81)" -gt 50
tis-movie --no-mark --format ppm -o - "$T/frames.mesh" >"$T/n.ppm"
ok "--no-mark: no green" test "$(pixels "$T/n.ppm" 3 0 166 81)" -eq 0
tis-movie --junction 2 3 --format ppm -o - "$T/frames.mesh" >"$T/j.ppm"
ok "--junction A B marks that one" test "$(pixels "$T/j.ppm" 0 0 166 81)" -gt 50 -a "$(cmp -s "$T/j.ppm" "$T/f.ppm"; echo $?)" -eq 1
# a honeycomb: every junction's tension is 4 (P_hex - p0), red above p0
# and blue below; at --scale equal to it, full colour
tis-hex 4 4 --p0 3.6 | tis-movie --scale 0.4896777456 --format ppm -o - >"$T/red.ppm"
tis-hex 4 4 --p0 3.9 | tis-movie --scale 0.7103222544 --format ppm -o - >"$T/blue.ppm"
ok "tension 4 (P_hex - 3.6) > 0 at full scale: red junctions, no blue" \
	test "$(pixels "$T/red.ppm" 0 180 4 38)" -gt 1000 -a "$(pixels "$T/red.ppm" 0 59 76 192)" -eq 0
ok "tension 4 (P_hex - 3.9) < 0: blue junctions, no red" \
	test "$(pixels "$T/blue.ppm" 0 59 76 192)" -gt 1000 -a "$(pixels "$T/blue.ppm" 0 180 4 38)" -eq 0
tis-movie --window 3 --format ppm -o - "$T/frames.mesh" >"$T/w.ppm"
gw=$(pixels "$T/w.ppm" 3 0 166 81) gf=$(pixels "$T/f.ppm" 3 0 166 81)
# the view 3 wide of a box 4 sqrt(2/sqrt 3) = 4.2983 wide: lengths and
# line widths (0.06 of a length unit, under their cap) 1.4328 times, the
# green band's area 2.053 times
ok "--window 3: the marked junction 2.05 times the pixels ($gw, $gf in the whole box)" \
	awk -v a="$gw" -v b="$gf" 'BEGIN { r = a / b; exit !(r > 1.95 && r < 2.15) }'
fails_with 2 "--window with --no-mark" tis-movie --window 3 --no-mark -o "$T/x.mp4" "$T/frames.mesh"
ok "the same frames, the same bytes" sh -c "tis-movie --format ppm -o - '$T/frames.mesh' | cmp -s - '$T/f.ppm'"
tis-vtk -o "$T/run" "$T/frames.mesh"
tis-movie --format ppm -o - "$T/run.pvd" >"$T/pvd.ppm"
ok "a .pvd of the run gives the stream's frames, byte for byte" cmp -s "$T/pvd.ppm" "$T/f.ppm"

fails_with 2 "no -o" tis-movie "$T/frames.mesh"
fails_with 2 "-o with an unknown suffix" tis-movie -o "$T/x.avi" "$T/frames.mesh"
fails_with 2 "-o - without --format ppm" tis-movie -o - "$T/frames.mesh"
fails_with 2 "--fps 0" tis-movie --fps 0 -o "$T/x.mp4" "$T/frames.mesh"
printf 'tismesh 1\nbox 1 1\nvertices 3\n0 0\n' >"$T/bad.mesh"
fails_with 1 "a malformed mesh" tis-movie -o "$T/x.mp4" "$T/bad.mesh"
: >"$T/empty"
fails_with 1 "no frame" tis-movie -o "$T/x.mp4" "$T/empty"
echo '<VTKFile type="Collection"><Collection></Collection></VTKFile>' >"$T/none.pvd"
fails_with 1 "a .pvd without datasets" tis-movie -o "$T/x.mp4" "$T/none.pvd"
sed 's/Box/Bogus/' "$T/run-0000.vtp" >"$T/run-0000b.vtp"; sed 's/run-0000.vtp/run-0000b.vtp/' "$T/run.pvd" >"$T/b.pvd"
fails_with 1 "a .vtp without its box" tis-movie -o "$T/x.mp4" "$T/b.pvd"
{ tis-hex 4 4; tis-hex 4 6; } >"$T/two.mesh"
fails_with 1 "frames with different boxes" tis-movie -o "$T/x.mp4" "$T/two.mesh"
fails_with 1 "--junction that is not one" tis-movie --junction 0 9 -o "$T/x.mp4" "$T/frames.mesh"
fails_with 1 "ffmpeg missing" tis-movie --ffmpeg "$T/no-such-ffmpeg" -o "$T/x.mp4" "$T/frames.mesh"

if command -v ffmpeg >/dev/null 2>&1 && command -v ffprobe >/dev/null 2>&1; then
	probe() { ffprobe -v error -count_frames -select_streams v:0 \
		-show_entries stream=nb_read_frames,width,height:format=duration -of default=nw=1 "$1"; }
	tis-movie --fps 5 -o "$T/m.mp4" "$T/frames.mesh" 2>"$T/err"
	probe "$T/m.mp4" >"$T/p" 2>&1
	ok "MP4: ffprobe reads $nf frames of 496 x 458 lasting $nf/5 s" sh -c "
		grep -qx 'nb_read_frames=$nf' '$T/p' && grep -qx 'width=496' '$T/p' && grep -qx 'height=458' '$T/p' &&
		awk -F= '\$1 == \"duration\" { d = \$2 - $nf / 5; exit !(d * d < 1e-6) }' '$T/p'" || sed 's/^/#   /' "$T/p"
	tis-movie --fps 10 -o "$T/m.gif" "$T/frames.mesh" 2>"$T/err"
	probe "$T/m.gif" >"$T/p" 2>&1
	ok "GIF: ffprobe reads $nf frames lasting $nf/10 s" sh -c "
		grep -qx 'nb_read_frames=$nf' '$T/p' &&
		awk -F= '\$1 == \"duration\" { d = \$2 - $nf / 10; exit !(d * d < 1e-4) }' '$T/p'" || sed 's/^/#   /' "$T/p"
	fails_with 1 "ffmpeg failing (a directory that does not exist): its message, one line" \
		tis-movie -o "$T/no/such/dir/m.mp4" "$T/frames.mesh"
else
	skip 3 "ffmpeg or ffprobe missing"
fi
done_testing
