// The emitted tables are faithful: every kernel of generated/ compiles (with
// -Wall -Wextra -Werror), its normalisation is the correctly rounded exact
// constant, and every quantity evaluated straight from the table
// (table::evaluate, the unoptimised reference) matches the exact value at
// sample radii, including the support edge and outside it.
#include "emit_round.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "rounding.hpp"
#include "sanitized.hpp"

#include <mollify/detail/evaluate.hpp>
#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

using namespace mollify::gen;
namespace table = mollify::table;

namespace {

const std::vector<Q> sample_radii = {Q(0),     Q(1, 1000), Q(1, 8),  Q(1, 3),   Q(1, 2),  Q(2, 3),    Q(3, 4),
                                     Q(7, 8),  Q(99, 100), Q(999, 1000), Q(1), Q(101, 100), Q(3, 2), Q(4)};

bool singular_at_zero(const Radial& f) {
    for (const auto& [k, p] : f.pieces.front().terms())
        if (p.low() < 0 || k.basis == Basis::log || k.basis == Basis::arcsech) return true;
    return false;
}

// The exact value correctly rounded; nullopt where the quantity is singular.
std::optional<double> exact_double(const Radial& f, const Q& r) {
    const ClosedForm& form = f.form_at(r);
    if (form.is_elementary()) return round_to_double(form.at(r));
    if (r == 1) {
        const auto v = value_at_one(form);
        return v ? std::optional<double>(round_to_double(*v)) : std::nullopt;
    }
    return round_to_double([&](unsigned bits) {
        Real rr(0, bits * 30103 / 100000 + 2);
        mpfr_set_q(rr.backend().data(), r.backend().data(), MPFR_RNDN);
        return form.evaluate(rr, bits);
    });
}

}  // namespace

TEST(Tables, EveryKernelMatchesItsExactValues) {
    int checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        const ExactKernel k = make_kernel(parse_spec(t->spec), t->dim);
        const Quantities q = derive_quantities(k);
        EXPECT_EQ(t->normalisation, round_to_double(k.normalisation)) << t->spec;
        EXPECT_EQ(std::string(t->normalisation_exact), k.normalisation.to_string()) << t->spec;
        EXPECT_EQ(t->has_potential, k.claims.no_potential.empty()) << t->spec;
        for (int i = 0; i < table::quantity_count; ++i) {
            const std::string& name = quantity_names()[static_cast<std::size_t>(i)];
            if (!t->has_potential && table::is_potential(static_cast<table::QuantityId>(i))) {
                EXPECT_EQ(t->quantities[i].npieces, 0);
                continue;
            }
            const Radial& f = quantity(k, q, name);
            std::vector<std::pair<double, double>> values;  // (table, exact)
            double scale = 0;
            for (const Q& r : sample_radii) {
                if (r == 0 && singular_at_zero(f)) continue;
                // Near r = 0 the tables of missing Wendland functions hold the exact
                // series instead of their closed forms (which cancel there); the
                // closed form is only compared at these samples away from 0, the
                // series in SeriesPiecesAreAccurateToAFewUlp.
                if (!f.form_at(r).is_elementary() && r < Q(1, 8)) continue;
                const auto exact = exact_double(f, r);
                if (!exact) continue;
                values.emplace_back(table::evaluate(t->quantities[i], round_to_double(r)), *exact);
                scale = std::max(scale, std::abs(*exact));
            }
            // A wrong coefficient, basis or piece is an O(1) relative error; the
            // reference evaluator's own rounding (Horner over <= 40 terms of
            // condition < 1e4 near cancellation) stays below 1e-11 of the scale.
            for (std::size_t j = 0; j < values.size(); ++j)
                EXPECT_NEAR(values[j].first, values[j].second, 1e-11 * scale + 1e-300)
                    << t->spec << " D=" << t->dim << " " << name << " sample " << j;
            ++checked;
        }
    }
    EXPECT_GT(checked, 2000);
}

namespace {

// The exact value at a double r, correctly rounded.
double exact_at(const Radial& f, double r) {
    return round_to_double([&](unsigned bits) {
        Real rr(0, bits * 30103 / 100000 + 2);
        mpfr_set_d(rr.backend().data(), r, MPFR_RNDN);
        return f.evaluate(rr, bits);
    });
}

// Error of the table at r in ulps of the exact value (of `scale` where the
// exact value is below 1e-10 of it).
double ulps(const table::Quantity& q, const Radial& f, double r, double scale) {
    const double exact = exact_at(f, r);
    const double ref = std::abs(exact) >= 1e-10 * scale ? std::abs(exact) : scale;
    return std::abs(table::evaluate(q, r) - exact) / (std::ldexp(1.0, std::ilogb(ref) - 52));
}

double max_abs(const Radial& f) {
    double m = 0;
    for (int j = 1; j <= 64; ++j) m = std::max(m, std::abs(exact_at(f, j / 64.0)));
    return m;
}

}  // namespace

// The first piece of every missing Wendland quantity is its exact series at
// r = 0 (generator/series.hpp): relative accuracy down to r = 1e-300, where
// the closed forms lose everything (r^-k terms overflow, S/r - 1/r cancels).
TEST(Tables, SeriesPiecesAreAccurateToAFewUlp) {
    int checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        if (std::string(t->spec).rfind("wendland-missing:", 0) != 0) continue;
        if (mollify::testing::left_to_optimised_build(t->spec)) continue;
        const ExactKernel k = make_kernel(parse_spec(t->spec), t->dim);
        const Quantities q = derive_quantities(k);
        for (int i = 0; i < table::quantity_count; ++i) {
            const Radial& f = quantity(k, q, quantity_names()[static_cast<std::size_t>(i)]);
            const table::Quantity& tq = t->quantities[i];
            ASSERT_GT(tq.npieces, 2);
            const double r0 = tq.pieces[0].hi, scale = max_abs(f);
            for (double r = r0 * (1 - 0x1p-20); r > 1e-300; r *= 0.0123) {
                EXPECT_LE(ulps(tq, f, r, scale), 4) << t->spec << " D=" << t->dim << " quantity " << i << " r=" << r;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, mollify::testing::sanitized_build ? 10000 / 6 : 10000);  // one missing function of six
}

// 2D potentials near the support edge, where phi ~ (r - 1)/(2 pi) -> 0: the
// last piece is log r terms + the Taylor polynomial at the edge, so the
// relative accuracy holds down to 1 - r = 1e-15 (the plain polynomial lost
// up to 1e5 ulp).
TEST(Tables, TwoDimensionalPotentialsKeepRelativeAccuracyAtTheEdge) {
    int checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        if (t->dim != 2 || !t->has_potential || std::string(t->spec).rfind("wendland-missing:", 0) == 0) continue;
        const ExactKernel k = make_kernel(parse_spec(t->spec), t->dim);
        const Quantities q = derive_quantities(k);
        const int i = static_cast<int>(table::QuantityId::potential);
        const Radial& f = quantity(k, q, "potential");
        const double scale = max_abs(f);
        for (double d = 0.1; d > 1e-15; d *= 0.31) {
            EXPECT_LE(ulps(t->quantities[i], f, 1 - d, scale), 4) << t->spec << " 1 - r = " << d;
            ++checked;
        }
    }
    EXPECT_GT(checked, 1000);
}

TEST(Tables, CatalogueHoldsTheDefaultKernels) {
    std::set<std::string> specs;
    for (const table::Kernel* t : mollify::tables::all_kernels) specs.insert(std::string(t->spec) + "@" + std::to_string(t->dim));
    for (const char* s : {"mollifier:M=9,order=6@3", "wendland:k=4,l=4@2", "combo:m=3,base=wendland:k=3,l=2@1",
                          "combo:m=3,base=mollifier:M=9@3", "poly6@1", "viscosity@2", "box-d2@1", "cubic-spline@3"})
        EXPECT_TRUE(specs.count(s)) << s;
    EXPECT_FALSE(specs.count("viscosity@1"));
}

namespace {

// The exact value of a piecewise polynomial/log quantity at a double r > 0,
// correctly rounded (0 where it vanishes exactly).
double exact_value(const Radial& f, double r) {
    const Exact x = f.at(Q(r));
    return x.is_zero() ? 0.0 : round_to_double(x);
}

}  // namespace

// Every factored term names its own edge (table::Term::edge): for a single
// kernel the upper breakpoint of its piece (or the support edge), for a combination W = sum_j w_j
// psi_{a_j} (Franz (4.17)) the radius a_j of the term it comes from.
TEST(Tables, TermsAreFactoredAtTheirOwnEdges) {
    int checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        const Spec spec = parse_spec(t->spec);
        std::set<double> edges;
        if (spec.family == Family::combo)
            for (const Q& a : radii(spec)) edges.insert(round_to_double(a));
        for (const table::Quantity& q : t->quantities)
            for (int p = 0; p < q.npieces; ++p)
                for (int i = 0; i < q.pieces[p].nterms; ++i) {
                    const table::Term& term = q.pieces[p].terms[i];
                    if (term.edge_power == 0) {
                        EXPECT_EQ(term.edge, q.pieces[p].hi) << t->spec;
                    } else if (spec.family == Family::combo) {
                        EXPECT_TRUE(edges.count(term.edge) && term.edge >= q.pieces[p].hi) << t->spec << " edge " << term.edge;
                    } else {
                        // The piece's upper breakpoint, or the support edge where a
                        // piece next to it was split (Taylor pieces in between).
                        EXPECT_TRUE(term.edge == q.pieces[p].hi || term.edge == t->support) << t->spec;
                    }
                    ++checked;
                }
    }
    EXPECT_GT(checked, 10000);
}

// The double-double parts of Precision::accurate (table::Term::c_lo,
// edge_lo): each low part is at most half an ulp of its high part (so
// hi + lo rounds to hi), and a combination's edges carry the exact
// rounding error of their radius a_j.
TEST(Tables, LowPartsAreTheRoundingErrors) {
    int with_low_parts = 0, edges_checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        const Spec spec = parse_spec(t->spec);
        std::map<double, double> edge_lo;  // round(a_j) -> a_j - round(a_j), rounded
        if (spec.family == Family::combo)
            for (const Q& a : radii(spec)) edge_lo[round_to_double(a)] = low_part(a, round_to_double(a));
        for (const table::Quantity& q : t->quantities)
            for (int p = 0; p < q.npieces; ++p)
                for (int i = 0; i < q.pieces[p].nterms; ++i) {
                    const table::Term& term = q.pieces[p].terms[i];
                    if (term.c_lo != nullptr) {
                        ++with_low_parts;
                        for (int k = 0; k < term.n; ++k) {
                            const double c = std::abs(term.c[k]), half_ulp = (std::nextafter(c, INFINITY) - c) / 2;
                            EXPECT_LE(std::abs(term.c_lo[k]), half_ulp) << t->spec << " c[" << k << "]";
                            EXPECT_EQ(term.c[k] + term.c_lo[k], term.c[k]) << t->spec << " c[" << k << "]";
                        }
                    }
                    if (term.edge_power != 0 && edge_lo.count(term.edge)) {
                        EXPECT_EQ(term.edge_lo, edge_lo.at(term.edge)) << t->spec << " edge " << term.edge;
                        ++edges_checked;
                    }
                }
    }
    EXPECT_GT(with_low_parts, 1000);
    EXPECT_GT(edges_checked, 100);
}

// Combinations on both sides of every radius a_j: each term w_j psi_{a_j}
// is factored at a_j, so W and W'/r (no interior zeros in psi, psi'/r)
// keep the accuracy of their terms, error < 32 ulp of sum_j |w_j f_j(r)|.
// Expanded at the piece's upper breakpoint they cancelled: up to 3e8 ulp.
TEST(Tables, CombinationsKeepTheAccuracyOfTheirTerms) {
    int checked = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        const Spec spec = parse_spec(t->spec);
        if (spec.family != Family::combo) continue;
        const ExactKernel k = make_kernel(spec, t->dim);
        const Quantities q = derive_quantities(k);
        const std::vector<ComboTerm> terms = combo_terms(k);
        for (const char* name : {"value", "grad_over_r"}) {
            const int i = name == std::string("value") ? static_cast<int>(table::QuantityId::value)
                                                       : static_cast<int>(table::QuantityId::grad_over_r);
            std::vector<Radial> parts;
            for (const ComboTerm& term : terms)
                parts.push_back(quantity(term.kernel, derive_quantities(term.kernel), name) * Exact(term.weight));
            for (const Q& a : radii(spec))
                for (int e = 2; e <= 50; e += 4)
                    for (double r : {round_to_double(a) * (1 - std::ldexp(1.0, -e)), round_to_double(a) * (1 + std::ldexp(1.0, -e))}) {
                        if (r > 1) continue;
                        double scale = 0;
                        for (const Radial& part : parts) scale += std::abs(exact_value(part, r));
                        const double error = std::abs(table::evaluate(t->quantities[i], r) - exact_value(quantity(k, q, name), r));
                        EXPECT_LE(error, 32 * std::ldexp(1.0, std::ilogb(scale) - 52)) << t->spec << " D=" << t->dim << " " << name << " r=" << r;
                        ++checked;
                    }
        }
    }
    EXPECT_GT(checked, 5000);
}

// table::Term::split (generator/emit_round.cpp: split_of) on the whole
// catalogue: (1) content * m_k is c_k to double-double accuracy; (2) Horner's
// rule on m in double is exact at the grid 2^-split over the piece (its ends,
// their neighbours, random grid points), against rational arithmetic: the
// proof's bounds in action; (3) split_horner's double-double is within
// 2^-61 of content p_m(q) at random q, at the grid's midpoints (the largest
// q - qa) and at the piece's ends: the remainder's bound (2^-62) plus the
// product's rounding.
TEST(Tables, SplitTermsAreExactAtTheirGridAndAccurateBetween) {
    std::mt19937_64 rng(2026);
    int terms = 0;
    const Q tolerance = Q(1) / Q(boost::multiprecision::mpz_int(1) << 61);
    for (const table::Kernel* t : mollify::tables::all_kernels)
        for (const table::Quantity& quantity : t->quantities)
            for (int p = 0; p + 1 < quantity.npieces; ++p) {
                const table::Piece& piece = quantity.pieces[p];
                for (int i = 0; i < piece.nterms; ++i) {
                    const table::Term& term = piece.terms[i];
                    if (term.split == 0) continue;
                    ++terms;
                    const std::string where = std::string(t->spec) + " D=" + std::to_string(t->dim) + " piece " +
                                              std::to_string(p) + " term " + std::to_string(i);
                    ASSERT_EQ(term.var, table::Var::r) << where;
                    const Q content = Q(term.content) + Q(term.content_lo);
                    for (int k = 0; k < term.n; ++k) {
                        const Q c = Q(term.c[k]) + Q(term.c_lo ? term.c_lo[k] : 0.0);
                        EXPECT_LE(abs(content * Q(term.m[k]) - c), abs(c) / Q(boost::multiprecision::mpz_int(1) << 100))
                            << where << " k=" << k;
                    }
                    auto exact = [&](const Q& x) {
                        Q sum = 0;
                        for (int k = term.n; k-- > 0;) sum = sum * x + Q(term.m[k]);
                        return sum;
                    };
                    const double grid = std::ldexp(1.0, -term.split);
                    const long long j0 = std::llround(piece.lo / grid), j1 = std::llround(piece.hi / grid);
                    std::vector<long long> js = {j0, j0 + 1, j1 - 1, j1};
                    std::uniform_int_distribution<long long> pick(j0, j1);
                    for (int n = 0; n < 40; ++n) js.push_back(pick(rng));
                    for (const long long j : js) {
                        const double qa = static_cast<double>(j) * grid;
                        double a = term.m[term.n - 1];
                        for (int k = term.n - 2; k >= 0; --k) a = std::fma(a, qa, term.m[k]);
                        ASSERT_EQ(Q(a), exact(Q(qa))) << where << " qa=" << qa;
                    }
                    std::uniform_real_distribution<double> u(piece.lo, piece.hi);
                    std::vector<double> qs = {piece.lo, piece.hi, std::nextafter(piece.hi, 0.0)};
                    for (int n = 0; n < 20; ++n) qs.push_back(u(rng));
                    for (int n = 0; n < 20; ++n) qs.push_back((static_cast<double>(pick(rng)) + 0.5) * grid);
                    for (const double q : qs) {
                        if (!(q >= piece.lo && q <= piece.hi)) continue;
                        const mollify::detail::DoubleDouble y = mollify::detail::split_horner(
                            term.m, term.n, mollify::detail::split_constant(term.split), term.content, term.content_lo, q, 0.0);
                        const Q want = content * exact(Q(q));
                        EXPECT_LE(abs(Q(y.hi) + Q(y.lo) - want), tolerance * abs(want)) << where << " q=" << q;
                    }
                }
            }
    EXPECT_GT(terms, 1000);
}

// split_of proves or refuses: Wendland C4's polynomial splits at 2^-23 (2
// steps of 23 bits and 35 + 18 + 3 < 2^6); mixed signs may cancel; and
// 1 + 2^20 q is exact at 2^-26 but its remainder, ~2^-27 2^20 with a
// gamma_12 error, is not below 2^-62 of p(0) = 1.
TEST(Tables, SplitIsProvenOrRefused) {
    const Exact pi = Exact::pi_power(Q(1), -1);
    const Split c4 = split_of({pi * Q(495, 32), pi * Q(1485, 16), pi * Q(5775, 32)}, Q(0), Q(1));
    EXPECT_EQ(c4.bits, 23);
    EXPECT_EQ(c4.m, (std::vector<Q>{Q(3), Q(18), Q(35)}));
    EXPECT_EQ(c4.content, pi * Q(165, 32));
    EXPECT_EQ(split_of({Exact(Q(1)), Exact(Q(-2))}, Q(0), Q(1)).bits, 0);
    EXPECT_EQ(split_of({Exact(Q(1)), Exact(Q(1 << 20))}, Q(0), Q(1)).bits, 0);
    EXPECT_EQ(split_of({Exact(Q(1)), Exact(Q(1 << 20))}, Q(1, 2), Q(1)).bits, 26);  // p >= 2^19 there
}
