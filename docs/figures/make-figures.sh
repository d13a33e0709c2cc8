#!/usr/bin/env bash
# Remakes the figures in docs/figures from a release build (scripts/build). Each command is
# listed in docs/figures/README.md next to its image.
set -euo pipefail
cd "$(dirname "$0")/../.."
sf=build/release/shaderfit
out=docs/figures

# Seed 001: aluminium, with the shape parameter s fitted to it.
$sf plot curves --material aluminium --fit s -o $out/aluminium.png \
  --title "Aluminium at 632.8 nm (n = 1.373 + 7.618i, Sopra via Filmetrics)" \
  "Schlick=r0 + (1 - r0)*x^5" "seed 001=r0 + (x - r0)*x^4" "shape form=r0 + (1 - r0 - s*cos_theta)*x^4"

# Seed 001: the exact reflectance of the seed's materials (IOR 1.5 and the seven metals).
$sf plot curves --material seed -o $out/seed-materials.png --title "Exact Fresnel reflectance of the seed 001 materials"

# Seed 001: the error of both approximations on the seed data set, dielectrics and metals.
$sf plot curves --dataset fresnel-seed --x cos_theta --group kind --errors --points -o $out/seed-errors.png \
  --title "Error against exact Fresnel on the seed data set (seed 1)" \
  "Schlick=r0 + (1 - r0)*x^5" "seed 001=r0 + (x - r0)*x^4"

# Seed 002: reference / approximation / difference for a sphere, roughness 0.3, F0 0.04.
$sf plot sphere --roughness 0.3 --f0 0.04 -o $out/sphere.png
