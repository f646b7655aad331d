#!/bin/sh
# cellGPU (github:sussmanLab/cellGPU) side by side with tis: a smoke run of
# its CPU path.  cellGPU is a benchmark subject, never part of tis: it is
# built outside the repository (CELLGPU_BUILD, default /work/cellgpu-build)
# and this script skips cleanly when it is not there, so `make bench`
# works on CI.
#
# Building it on Debian 12 with CUDA 13.0 (no GPU) took these local patches
# to cellGPU's tree, none of them to tis:
#   CMakeLists.txt: project(... LANGUAGES C CXX) (FindHDF5 try-compiles C);
#     CMAKE_CUDA_ARCHITECTURES 50 -> 75 (CUDA 13 has no sm_50);
#     INTERPROCEDURAL_OPTIMIZATION OFF on modelGPU updatersGPU utilityGPU
#     and " -dlto " removed from build/CMakeFiles/*.out.dir/dlink.txt (the
#     toolkit has no libnvvm, so nvlink cannot do device LTO);
#   inc/std_include.h: prop.memoryClockRate -> 0 (removed in CUDA 13).
#   apt-get install libhdf5-dev libeigen3-dev; cmake ..
#     -DCMAKE_CUDA_COMPILER=/usr/local/cuda/bin/nvcc; make
# With that, Vertex.out links but its CPU run (-g -1) still calls
# noiseSource::initializeGPURNGs, which throws without a GPU; two more
# local patches make it run:
#   src/utility/noiseSource.cpp, initializeGPURNGs: return at once when
#     cudaGetDeviceCount reports no device;
#   Vertex.cpp: the timed loop writes its netCDF database only with -z 1.
# The timing is then cellGPU's own random tissue against tis's perturbed
# honeycomb (bench/RESULTS.md, "The kernel"): not the same tissue, so no
# energy check; a same-tissue driver is not written.
set -e
cd "$(dirname "$0")/.."
B=${CELLGPU_BUILD:-/work/cellgpu-build}/build/Vertex.out
if [ ! -x "$B" ]; then
	echo "cellgpu.sh: cellGPU not built at $B, skipped"
	exit 0
fi
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
E=bench/out/energy-bench
[ -x "$E" ] || { echo "cellgpu.sh: $E not built (run bench/energy.sh first), skipped"; exit 0; }
for n in 324 1024 4096; do
	if (cd "$d" && "$B" -n $n -g -1 -t $((4000000 / n)) -i 10 -p 3.7) > "$d/log" 2>&1; then
		printf 'cells %s: cellGPU %s s per step; tis (cells vertices eg_us eg_ns step_us step_ns): ' \
			$n "$(sed -n 's/.*per iteration currently at //p' "$d/log")"
		"$E" --steps $n | tail -1
	else
		echo "cellgpu.sh: cellGPU's CPU run failed (see the comment above), skipped:"
		tail -2 "$d/log"
		exit 0
	fi
done
