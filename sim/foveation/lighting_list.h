// The registration list of the lighting strategies (lighting.h): one line per strategy, read by
// lighting_table(). Each strategy's file defines create_lighting_<name> and
// lighting_<name>_params (its parameter declaration).
//   FOVSIM_LIGHTING(name, summary)
FOVSIM_LIGHTING(all_vpls,
                "every VPL at every shaded sample: tile-based deferred shading, the ground truth "
                "of Yang et al., \"Foveated light culling\" §7")
FOVSIM_LIGHTING(
    flc,
    "foveated light culling (Yang et al., \"Foveated light culling\" §4-§5): importance "
    "map, quasi-MH shading points, eq. 14 contributions with BLSO visibility, "
    "stochastic culling to a VPL budget")
FOVSIM_LIGHTING(fir,
                "foveated instant radiosity as the FLC paper describes it (§1, §7): importance "
                "from visibility and position relative to the fovea only, VPL intensity ignored, "
                "stochastic culling to a VPL budget")
FOVSIM_LIGHTING(uniform,
                "a uniform random subset of vpl_budget VPLs (Horvitz-Thompson weights): the "
                "control for flc and fir, the same budget and culling without foveation")
