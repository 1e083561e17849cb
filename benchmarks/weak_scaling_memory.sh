#!/bin/bash
# benchmarks/weak_scaling_memory.sh BUILD_DIR [LOCAL] [STEPS]: peak resident memory per
# rank with a fixed number of local cells (LOCAL^3 per rank, default 32) on 1, 2, 4 and 8
# ranks (oversubscribed beyond the cores: memory, not time, is measured). The scene is a
# uniform 3D granular gas under gravity with the implicit step (SDIRK2), periodic in x and
# y, walls in z; the box doubles along x, then y, then z. Prints the run summary's "peak
# resident" (largest rank) per rank count and its ratio to 1 rank.
set -e
B=$(readlink -f ${1:-build}); L=${2:-32}; STEPS=${3:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
W=$(mktemp -d /tmp/weak.XXXX)
base=""
printf "%6s %14s %22s %8s\n" ranks cells "peak MiB (max rank)" ratio
for P in 1 2 4 8; do
  case $P in 1) f=(1 1 1);; 2) f=(2 1 1);; 4) f=(2 2 1);; 8) f=(2 2 2);; esac
  nx=$((L*f[0])); ny=$((L*f[1])); nz=$((L*f[2]))
  cat > $W/scene.prm <<PRM
set Dimension = 3
subsection Domain
  set Lower corner = 0, 0, 0
  set Upper corner = $(awk "BEGIN{print 0.001*$nx}"), $(awk "BEGIN{print 0.001*$ny}"), $(awk "BEGIN{print 0.001*$nz}")
  set Cells = $nx, $ny, $nz
  set Boundary x- = periodic
  set Boundary x+ = periodic
  set Boundary y- = periodic
  set Boundary y+ = periodic
  set Boundary z- = no-slip wall
  set Boundary z+ = slip wall
end
subsection Material
  set Model = granular
  set Restitution coefficient = 0.8
end
subsection Effects
  set Gravity = 0, 0, -9.81
end
subsection Initial state
  set Packing fraction = 0.3 + 0.2*sin(2*pi*x/0.016)*sin(2*pi*y/0.016)
  set Velocity = 0.02*sin(2*pi*x/0.016); 0; 0
  set Temperature = 1e-7
end
subsection Diffusion step
  set Integrator = sdirk2
end
subsection Time
  set End time = 1
  set Maximum steps = $STEPS
end
subsection Output
  set Directory = $W/out
  set Write VTU = false
  set Write profiles = false
  set Write checkpoint = false
end
PRM
  LD_LIBRARY_PATH=$B mpirun ${MPIRUN_ARGS:-} --oversubscribe -n $P $B/granhydro $W/scene.prm > $W/log-$P 2>&1 || { tail -5 $W/log-$P; exit 1; }
  mib=$(grep -o "peak resident [0-9.]*" $W/log-$P | awk '{print $3}')
  [ -z "$base" ] && base=$mib
  printf "%6d %14d %22.1f %8.3f\n" $P $((nx*ny*nz)) $mib $(awk "BEGIN{print $mib/$base}")
done
rm -rf $W
