#!/bin/bash
# The shipped speed/accuracy studies (studies/README.md, docs/choosing-settings.md).
#
#   scripts/run_studies.sh [--out DIR] [NAME ...]       (default DIR: runs/studies; all studies)
#
# NAME: bar, bar_edge, droplet, droplet_edge, spurious, spurious_form, lame, lame_edge, entry, drainage, drainage_edge,
# damage_plate, damage_plate_crossing, damage_plate_edge. Each runs
# `poresph study` on one thread (OMP_NUM_THREADS=1, --threads 1) into DIR/NAME and copies its
# DIR/NAME/study.png to docs/img/study_NAME.png. Run from the repository root after a build.
set -u
out=runs/studies
if [ "${1:-}" = "--out" ]; then out=$2; shift 2; fi
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(bar bar_edge droplet droplet_edge spurious spurious_form lame lame_edge entry drainage drainage_edge damage_plate damage_plate_crossing damage_plate_edge)
exe=build/poresph
export OMP_NUM_THREADS=1
study() {  # NAME SCENE ARGS...
  local name=$1 scene=$2; shift 2
  echo "== $name: poresph study $scene $* --out $out/$name --threads 1 --cost cpu"
  $exe study "$scene" "$@" --out "$out/$name" --threads 1 --cost cpu --overwrite || echo "== $name: exit $?"
  [ -f "$out/$name/study.png" ] && cp "$out/$name/study.png" "docs/img/study_$name.png"
}
for n in "${names[@]}"; do
  case $n in
    bar)       # convergence in dx, kernel and h/dx against T = 2L/c
      study bar studies/vibrating_bar.yaml --vary spacing=2.666e-3,1.333e-3,6.665e-4,3.3325e-4 \
        --vary kernel=cubic,wendland --vary h_over_dx=1.3,2.5 ;;
    bar_edge)  # the largest stable fixed step and the smallest h/dx
      study bar_edge studies/vibrating_bar.yaml --vary dt=2e-8,8e-8,1.2e-7,1.6e-7 \
        --vary h_over_dx=0.8,1.0,1.3 ;;
    droplet)   # Laplace jump against gamma/R
      study droplet studies/static_droplet.yaml --vary spacing=3e-4,2.25e-4,1.5e-4,1e-4 \
        --vary kernel=quintic,wendland,cubic --vary h_over_dx=1.0,1.5 ;;
    droplet_edge)  # smallest h/dx and the density ratio gas : liquid
      study droplet_edge studies/static_droplet.yaml --set spacing=1.5e-4 \
        --vary h_over_dx=0.7,0.85,1.0 --vary materials.gas.density=1000,100 ;;
    spurious)  # spurious currents Ca = mu u_max / gamma
      study spurious studies/static_droplet_spurious.yaml --vary spacing=3e-4,2.25e-4,1.5e-4,1e-4 \
        --vary kernel=quintic,wendland --vary h_over_dx=1.0,1.5 ;;
    spurious_form)  # CSF against balanced-force CSF (a module option by its key path)
      study spurious_form studies/static_droplet_spurious.yaml --vary spacing=3e-4,1.5e-4,1e-4 \
        --vary fluid.surface_tension_form=csf,balanced --set kernel=wendland_c2 --set h_over_dx=1.5 ;;
    lame)      # hoop stress at 1.5 a against the closed form
      study lame studies/lame.yaml --vary spacing=1e-3,5e-4,2.5e-4 --vary kernel=cubic,wendland \
        --vary h_over_dx=1.3,1.6 ;;
    lame_edge) # the largest stable CFL and the smallest h/dx
      study lame_edge studies/lame.yaml --vary cfl=0.5,1.0 --vary h_over_dx=0.6,0.8,1.3 ;;
    entry)     # gas penetration into the slit against the finest run
      study entry studies/capillary_entry.yaml --vary spacing=2e-4,1e-4,5e-5 ;;
    drainage)  # gas saturation of a drained throat at percolation against the finest run
      study drainage studies/drainage_throat.yaml --vary spacing=1e-4,6.25e-5,5e-5 ;;
    drainage_edge) # the gas : water density ratio against the gas' sound speed at dx = 1e-4
      study drainage_edge studies/drainage_throat.yaml --vary materials.gas.density=1000,100,10 \
        --vary materials.gas.sound_speed=4,12.65,40 ;;
    damage_plate)  # AT-2 plate: imposed displacement at the first D >= 0.1 against the thesis' 17.4 um
      study damage_plate studies/damage_plate.yaml --vary spacing=4e-3,3e-3,2e-3 --vary cfl=0.5,0.9,1.0 \
        --set end_time=0.022 --set reference.value=1.74e-5 ;;
    damage_plate_crossing)  # the same plate: imposed displacement when the crack is through, finest run
      study damage_plate_crossing studies/damage_plate.yaml --vary spacing=4e-3,3e-3,2e-3 --vary cfl=0.5,1.0 \
        --set 'reference.at=first solid_damage_span_x >= 0.99' ;;
    damage_plate_edge)  # smallest h/dx and the largest fixed step at dx = 4 mm (crossing, finest run)
      study damage_plate_edge studies/damage_plate.yaml --set spacing=4e-3 --vary h_over_dx=1.25,1.0,0.8,0.6 \
        --vary dt=1.6e-5,3.2e-5,4.4e-5 --set 'reference.at=first solid_damage_span_x >= 0.99' ;;
    *) echo "unknown study '$n' (bar, bar_edge, droplet, droplet_edge, spurious, spurious_form, lame, lame_edge, entry, drainage, drainage_edge, damage_plate, damage_plate_crossing, damage_plate_edge)"; exit 2 ;;
  esac
done
