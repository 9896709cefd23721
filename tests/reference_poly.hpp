// A deliberately separate, minimal polynomial toolkit for tests: dense
// coefficient vectors over the rationals, written independently of the
// generator's Laurent class so that tests do not check the generator against
// itself.
#pragma once

#include "kernel.hpp"
#include "number.hpp"

#include <string>
#include <vector>

namespace mollify::gen::reference {

using Poly = std::vector<Q>;  // c[i] multiplies r^i

inline ExactKernel kernel(const std::string& spec, int dim) { return make_kernel(parse_spec(spec), dim); }

// omega_D = omega_rational(D) * pi^omega_pi(D): 2, 2 pi, 4 pi.
inline Q omega_rational(int D) { return D == 3 ? Q(4) : Q(2); }
inline int omega_pi(int D) { return D == 1 ? 0 : 1; }

inline Z fact(int n) {
    Z f = 1;
    for (int i = 2; i <= n; ++i) f *= i;
    return f;
}

inline Poly mul(const Poly& a, const Poly& b) {
    if (a.empty() || b.empty()) return {};
    Poly c(a.size() + b.size() - 1, Q(0));
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
    return c;
}

inline Poly power(const Poly& base, int n) {
    Poly p{Q(1)};
    for (int i = 0; i < n; ++i) p = mul(p, base);
    return p;
}

inline Q at(const Poly& p, const Q& r) {
    Q v = 0;
    for (std::size_t i = p.size(); i-- > 0;) v = v * r + p[i];
    return v;
}

inline Poly deriv(const Poly& p) {
    Poly d;
    for (std::size_t i = 1; i < p.size(); ++i) d.push_back(p[i] * static_cast<int>(i));
    return d;
}

// int_0^1 r^power p(r) dr.
inline Q integral01(const Poly& p, int power) {
    Q s = 0;
    for (std::size_t i = 0; i < p.size(); ++i) s += p[i] / (static_cast<int>(i) + power + 1);
    return s;
}

}  // namespace mollify::gen::reference
