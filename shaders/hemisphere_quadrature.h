// The quadrature rule for a hemisphere light's specular reflection, shared by C++
// (engine/reference/hemisphere_lobe.cpp) and GLSL (shaders/hemisphere_lobe.glsl), so that both
// renderers integrate with the same nodes. The rule and its measured error: docs/physics.md,
// "Hemisphere lights".
#ifndef METAMER_SHADERS_HEMISPHERE_QUADRATURE_H
#define METAMER_SHADERS_HEMISPHERE_QUADRATURE_H

// Gauss–Legendre on [−1, 1], 8 nodes: the 4 positive abscissae and their weights (the rule is
// symmetric). Used along each radial piece and along each arc.
#define HEMISPHERE_GAUSS_HALF 4
#define HEMISPHERE_GAUSS_X 0.18343464249564978, 0.52553240991632899, 0.79666647741362673, 0.96028985649753618
#define HEMISPHERE_GAUSS_W 0.36268378337836177, 0.31370664587788705, 0.22238103445337434, 0.10122853629037669

// Rings of half vectors per radial panel: 8 Gauss nodes in s = (n·h)^(N+1); each ring sampled at
// HEMISPHERE_RING_SAMPLES angles to find where the hemisphere's horizon cuts it, each cut refined
// by HEMISPHERE_ROOT_STEPS steps of false position (Illinois).
#define HEMISPHERE_RADIAL_PANELS 1
#define HEMISPHERE_RING_SAMPLES 32
#define HEMISPHERE_ROOT_STEPS 6
// Cuts of the radial integral: its ends, the two rings that touch the surface's horizon, and the
// extrema of n·h along the hemisphere's horizon (HEMISPHERE_HORIZON_SAMPLES samples, each extremum
// refined by HEMISPHERE_GOLDEN_STEPS golden-section steps).
#define HEMISPHERE_MAX_CUTS 10
#define HEMISPHERE_HORIZON_SAMPLES 16
#define HEMISPHERE_GOLDEN_STEPS 20

#endif
