// Wendland functions (seed 003, §4.3): generalised phi_{mu,alpha} = I^alpha f_mu
// with f_mu(r) = (1-r)_+^mu and I f(r) = int_r^1 s f(s) ds (Def. 4.28),
// up to a constant factor (fixed later by unit mass).
#pragma once

#include "closed_form.hpp"

namespace mollify::gen {

// Extended original Wendland psi_{d,k,l} = I^k f_{floor(d/2)+k+l+1} (Lemma 4.36).
Laurent wendland_shape(int d, int k, int l);
// Exponent of the factor (1-r)^n of psi_{d,k,l}: floor(d/2) + 2k + l + 1.
int wendland_edge_power(int d, int k, int l);
// Extended missing Wendland psi_{d,k+1/2,l} = I^(1/2) I^k f_{floor((d+1)/2)+k+l+1},
// as S(r) P(r) + L(r) Q(r) (Thm. 4.65), S = sqrt(1-r^2), L = arcsech r.
ClosedForm missing_wendland_shape(int d, int k, int l);

}  // namespace mollify::gen
