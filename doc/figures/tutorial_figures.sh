#!/bin/sh
# Remake the tutorial's pictures (doc/tutorial.md) by following it: the 1D column, the 2D
# box made from it, the 3D scene on two ranks. Needs the built granhydro (build/), mpirun,
# python3-matplotlib and ParaView's Python (paraview python3-paraview xvfb xauth).
#   sh doc/figures/tutorial_figures.sh [WORKDIR]     (default: a fresh temporary folder)
set -e
REPO=$(cd "$(dirname "$0")/../.." && pwd)
W=${1:-$(mktemp -d)}
mkdir -p "$W" && cd "$W"
ln -sfn "$REPO/build" build; ln -sfn "$REPO/parameters" parameters; ln -sfn "$REPO/tools" tools
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 MPLBACKEND=Agg
FIG="$REPO/doc/figures"

# step 1: the 1D column
build/granhydro parameters/sedimentation_column_1d.prm > step1.txt
/usr/bin/python3 tools/plot_profiles.py output-sedimentation-1d --title "1D column" \
  --out "$FIG/tutorial_column_1d_profiles.png"

# step 2: the 2D box, the tutorial's edits of the column's scene
sed -e 's/^set Dimension *= *1/set Dimension = 2/' \
    -e 's/^\( *\)set Lower corner *= *0$/\1set Lower corner = 0, 0/' \
    -e 's/^\( *\)set Upper corner *= *0\.1$/\1set Upper corner = 0.004, 0.1/' \
    -e 's/^\( *\)set Cells *= *100$/\1set Cells = 4, 100/' \
    -e 's/^\( *\)set Boundary x- *= *slip wall/\1set Boundary x- = periodic\n\1set Boundary y- = slip wall/' \
    -e 's/^\( *\)set Boundary x+ *= *slip wall/\1set Boundary x+ = periodic\n\1set Boundary y+ = slip wall/' \
    -e 's/^\( *\)set Gravity *= *-9.81/\1set Gravity = 0, -9.81/' \
    -e 's/^\( *\)set Velocity *= *0$/\1set Velocity = 0; 0/' \
    -e 's/output-sedimentation-1d/output-sedimentation-2d/' \
    -e '/set Write VTU *= *false/d' parameters/sedimentation_column_1d.prm > sedimentation_2d.prm
build/granhydro --check sedimentation_2d.prm
build/granhydro sedimentation_2d.prm > step2.txt
/usr/bin/python3 tools/compare_profiles.py output-sedimentation-1d output-sedimentation-2d
/usr/bin/python3 tools/plot_profiles.py output-sedimentation-2d --title "2D box" \
  --out "$FIG/tutorial_box_2d_profiles.png"
xvfb-run -a pvpython tools/paraview_picture.py output-sedimentation-2d --times 0,0.05,0.1,0.15 \
  --out "$FIG/tutorial_box_2d_paraview.png"

# step 3: the 3D scene on two ranks
mpirun -np 2 build/granhydro parameters/sedimentation-ci.prm > step3.txt
xvfb-run -a pvpython tools/paraview_picture.py output-sedimentation-ci \
  --out "$FIG/tutorial_sedimentation_3d_paraview.png"
echo "tutorial_figures: pictures in $FIG, runs in $W"
