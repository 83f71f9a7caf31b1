// JOD at a reduced render.scale (docs/fidelity.md, "JOD at the display's resolution").
//
// FovVideoVDP's JOD is absolute: a threshold such as fvvdp_jod_fl >= 9 decides "invisible or
// not". A run at render.scale < 1 samples the display at fewer pixels per degree, and its JOD
// moves with that (more than with many of the parameters studied). The fidelity ladder measured
// that bias against native resolution on the perception base for the rungs below; a JOD
// decision at one of them carries the bias (the value is judged at value -/+ bias, so the
// decision holds at native resolution as far as the measurement does), and at any other
// reduced scale the decision says plainly that it needs native resolution.
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"  // Json

namespace fovsim {

struct SearchConstraint;
struct Display;

// One measured rung: the largest |mean JOD at `scale` - mean JOD at render.scale 1| over the
// methods of the measurement (docs/fidelity.md names them).
struct JodBiasRung {
  double scale;
  double fvvdp_jod, fvvdp_jod_fl;
};
const std::vector<JodBiasRung>& jod_bias_rungs();

// The JOD metric a column belongs to ("fvvdp_jod" or "fvvdp_jod_fl", also for their summary
// forms _lo, _hi, _ci95); "" for any other column.
std::string jod_metric_of(const std::string& column);

// The manifest's fidelity.jod record of a run at `scale` on a display of `display_ppd` pixels
// per degree (FovVideoVDP's, at the display's own resolution; jod_display_ppd): render_scale,
// ppd_display, ppd_simulated, native (scale == 1), vs_render_scale 1, bias {fvvdp_jod,
// fvvdp_jod_fl} or null, needs_native (scale < 1 and no measured bias), note.
Json jod_fidelity_record(double scale, double display_ppd);
// FovVideoVDP's pixels per degree of display `d` at its own resolution (FvvdpDisplay).
double jod_display_ppd(const Display& d);

// The bias of `column`'s JOD metric in a jod record: 0 at native resolution, the measured bias
// at a measured rung, NaN when unknown (scale < 1, not measured) or not a JOD column.
double jod_bias_of(const Json& jod_record, const std::string& column);

// How a constraint on a JOD column is judged at a point: `margin` is added to the value's
// distance from each limit (the measured bias; 0 at native resolution or for other columns),
// `needs_native` when the run is below native resolution with no measured bias (then the value
// is judged as it is, and the verdict says the answer needs native resolution).
struct JodJudgement {
  double margin = 0;
  bool needs_native = false;
};
JodJudgement judge_jod(const SearchConstraint& c, const Json& jod_record);

// The verdict sentence for constraint `c` judged on `j` at a run described by `jod_record`
// ("" for a constraint that is not on a JOD column or at native resolution).
std::string jod_verdict_sentence(const SearchConstraint& c, const JodJudgement& j,
                                 const Json& jod_record);

}  // namespace fovsim
