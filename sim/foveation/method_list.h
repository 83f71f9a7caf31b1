// The registration list of every foveation method: one line per method, read by the factory
// table (factory.cpp) and the constructor declarations (methods.h). Adding a method = its own
// file (which defines create_<name> and <name>_params, the ParamInfo view of its ParamTable) +
// one line here + its test.
//   FOVSIM_METHOD(name, summary)
// The name is spelled here only: the method's file names itself with method_id::<name>
// (method_ids.h). What the GPU cost model charges the method declares in its own file
// (<name>_cost(), sim/foveation/method_cost.h; docs/architecture.md "Cost model").
// Mapping methods also expose their MappingSpec (FoveationMethod::mapping_spec), which
// `fovsim density` and the analytic counters of `predict` evaluate.
FOVSIM_METHOD(full, "full-resolution deferred shading (reference pipeline)")
FOVSIM_METHOD(flc, "foveated light culling of VPLs for indirect light (Yang et al. 2021)")
FOVSIM_METHOD(kfr, "kernel log-polar foveated rendering (Meng 2018 ch. 2)")
FOVSIM_METHOD(rmfr, "rectangular mapping-based foveated rendering (Ye et al. 2022 §3.2)")
FOVSIM_METHOD(hyperbolic, "Guenter three-layer baseline (Ye et al. 2022 §5.1)")
FOVSIM_METHOD(linear, "Weier linear fall-off baseline (Ye et al. 2022 §5.1)")
FOVSIM_METHOD(fvrs, "foveated coarse-pixel shading baseline (Franke et al. 2021 §8.4)")
FOVSIM_METHOD(
    twfr, "time-warped foveated rendering: reprojection + confidence redraw (Franke et al. 2021)")
FOVSIM_METHOD(
    rmfr_auto,
    "RMFR with f_x, f_y chosen per frame from peripheral edge orientation (Ye et al. 2022 "
    "§4.4.1, §7 future work)")
