// FovVideoVDP v1.2 (Mantiuk et al. 2021): placeholder until the metric core lands.
#pragma once

namespace fovsim {
// JOD of a pooled quality Q (spec §11): 10 - 0.0161713 Q^0.5915616342.
double fvvdp_jod_from_q(double mean_q);
}  // namespace fovsim
