// Certificates (certificate.hpp): exact proofs per kernel and dimension of
// unit mass (or Belley's derivative normalisations), vanishing moments up to
// the claimed order, Delta phi = W, and continuity of W (to the claimed
// smoothness) and of phi, phi'.
//
// Two directions: every catalogue kernel passes, and every kind of certificate
// fails when its property is deliberately broken (perturbed mass, perturbed
// combination weight, over-claimed smoothness or order). The expected
// certificate counts are checked too, so an empty or shortened list cannot
// pass vacuously.
#include "catalogue.hpp"
#include "certificate.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "spec.hpp"
#include "vandermonde.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace mollify::gen {
namespace {

ExactKernel kernel(const std::string& spec, int dim) { return make_kernel(parse_spec(spec), dim); }

std::vector<Certificate> certificates(const ExactKernel& k) { return certify(k, derive_quantities(k)); }

// Names (and details) of the failed certificates, "" when all pass.
std::string failures(const std::vector<Certificate>& cs) {
    std::string out;
    for (const Certificate& c : cs)
        if (!c.passed) out += "[" + c.what + ": " + c.detail + "] ";
    return out;
}

bool failed(const std::vector<Certificate>& cs, const std::string& what) {
    return std::any_of(cs.begin(), cs.end(), [&](const Certificate& c) { return !c.passed && c.what == what; });
}

bool has(const std::vector<Certificate>& cs, const std::string& what) {
    return std::any_of(cs.begin(), cs.end(), [&](const Certificate& c) { return c.what == what; });
}

// How many certificates a kernel must get: normalisation (1, or 2 for
// box-d2), one per vanishing moment, one for the exact order, (s+1) per
// breakpoint for C^s continuity, and for a potential 1 + 2 per breakpoint.
std::size_t expected_count(const ExactKernel& k) {
    std::size_t n = k.normalised_by == Normalisation::second_derivative ? 2 : 1;
    if (k.normalised_by == Normalisation::unit_mass) n += static_cast<std::size_t>(k.claims.order / 2 - 1) + 1;
    const std::size_t breaks = k.W.breaks.size() - 1;
    if (k.claims.smoothness >= 0) n += static_cast<std::size_t>(k.claims.smoothness + 1) * breaks;
    if (k.claims.no_potential.empty()) n += 1 + 2 * breaks;
    return n;
}

TEST(Certificate, WholeCataloguePasses) {
    const std::vector<CatalogueEntry> entries = expand_dimensions(default_specs());
    EXPECT_GT(entries.size(), 200u);
    for (const CatalogueEntry& e : entries) {
        const ExactKernel k = make_kernel(e.spec, e.dim);
        const std::vector<Certificate> cs = certificates(k);
        const std::string what = spec_string(e.spec) + " in D = " + std::to_string(e.dim);
        EXPECT_EQ(failures(cs), "") << what;
        EXPECT_EQ(cs.size(), expected_count(k)) << what;
    }
}

// The certificate list of one kernel, by name (mollifier M = 4, order 6, 3D: C^3,
// moments |x|^2, |x|^4 zero, |x|^6 not, potential).
TEST(Certificate, NamesForOneKernel) {
    const std::vector<Certificate> cs = certificates(kernel("mollifier:M=4,order=6", 3));
    for (const char* name : {"unit mass", "moment |x|^2 = 0", "moment |x|^4 = 0", "moment |x|^6 != 0 (order exactly 6)",
                             "W continuous at r = 1", "W^(3) continuous at r = 1", "Delta phi = W identically",
                             "phi continuous at r = 1", "phi^(1) continuous at r = 1"})
        EXPECT_TRUE(has(cs, name)) << name;
    EXPECT_FALSE(has(cs, "W^(4) continuous at r = 1"));
    EXPECT_EQ(failures(cs), "");
}

TEST(Certificate, MissingWendlandPasses) {
    for (const char* spec : {"wendland-missing:k=1,l=1", "wendland-missing:k=2,l=2", "wendland-missing:k=0",
                             "wendland-missing:k=3,l=1"})
        for (int D = 1; D <= 3; ++D) {
            const ExactKernel k = kernel(spec, D);
            const std::vector<Certificate> cs = certificates(k);
            EXPECT_EQ(failures(cs), "") << spec << " in D = " << D;
            EXPECT_EQ(cs.size(), expected_count(k)) << spec << " in D = " << D;
            // I^k f_{floor((D+1)/2)+k+l+1} ~ (1-r)^E, E = floor((D+1)/2) + 2k + l + 1 (each I adds 1
            // to the exponent), and I^(1/2) adds 1/2: psi ~ (1-r)^(E+1/2), so derivatives 0..E
            // vanish at r = 1 and the next is infinite: C^E.
            EXPECT_EQ(k.claims.smoothness, (D + 1) / 2 + 2 * k.spec.k + k.spec.l + 1) << spec << " in D = " << D;
        }
}

// Scale W by (1 + 10^-30): "unit mass" fails (and so does phi' at the edge, the
// potential carrying the wrong flux); everything else still holds.
TEST(Certificate, PerturbedMassFails) {
    const Q eps = pow(Q(10), -30);
    for (const char* spec : {"mollifier:M=9,order=6", "wendland:k=4,l=4", "combo:m=3,base=mollifier:M=9", "poly6",
                             "cubic-spline", "wendland-missing:k=1,l=1"})
        for (int D = 1; D <= 3; ++D) {
            ExactKernel k = kernel(spec, D);
            k.W = k.shape * (k.normalisation * (Q(1) + eps));
            const std::vector<Certificate> cs = certificates(k);
            EXPECT_TRUE(failed(cs, "unit mass")) << spec << " in D = " << D << ": " << failures(cs);
            if (k.claims.no_potential.empty()) {
                EXPECT_TRUE(failed(cs, "phi^(1) continuous at r = 1")) << spec << " in D = " << D;
                EXPECT_FALSE(failed(cs, "Delta phi = W identically")) << spec << " in D = " << D;
            }
        }
    // Adding 10^-6 (1-r^2)^9 to a kernel: the same.
    ExactKernel k = kernel("mollifier:M=9", 3);
    Laurent bump(Q(1));
    for (int i = 0; i < 9; ++i) bump = bump * (Laurent(Q(1)) - Laurent::monomial(Q(1), 2));
    k.W = k.W + Radial::single(ClosedForm(bump * Q(1, 1000000)));
    EXPECT_TRUE(failed(certificates(k), "unit mass"));
}

// Belley's kernels: a perturbed normalisation fails their own certificates.
TEST(Certificate, PerturbedBelleyNormalisationFails) {
    ExactKernel d1 = kernel("box-d1", 1);
    d1.W = d1.shape * (d1.normalisation * Q(999, 1000));
    EXPECT_TRUE(failed(certificates(d1), "int x W dx = -1 (f * W ~ f')"));
    ExactKernel d2 = kernel("box-d2", 1);
    d2.W = d2.shape * (d2.normalisation * Q(1001, 1000));
    const std::vector<Certificate> c2 = certificates(d2);
    EXPECT_TRUE(failed(c2, "int x^2 W dx = 2 (f * W ~ f'')"));
    EXPECT_FALSE(failed(c2, "zero mass"));
    // Unbalanced pieces break the zero mass.
    ExactKernel d3 = kernel("box-d2", 1);
    d3.W.pieces[1] = d3.W.pieces[1] * Q(2);
    EXPECT_TRUE(failed(certificates(d3), "zero mass"));
}

// A combination sum_j w_j psi_{a_j} (Franz (4.17)) rebuilt here; shifting epsilon
// from one weight to another keeps sum w_j = 1 (each psi_a has the base mass) but
// breaks the |x|^2 moment.
TEST(Certificate, PerturbedComboWeightFailsAMoment) {
    for (const char* base : {"wendland:k=2,l=1", "mollifier:M=9"})
        for (int D = 1; D <= 3; ++D) {
            const std::string spec = std::string("combo:m=3,base=") + base;
            ExactKernel k = kernel(spec, D);
            const ExactKernel b = kernel(base, D);
            const std::vector<Q> radii = equidistant_radii(3);
            auto build = [&](const std::vector<Q>& w) {
                Radial shape;
                for (std::size_t j = 0; j < w.size(); ++j) shape = shape + b.shape.scaled(radii[j], D) * Exact(w[j]);
                return shape * b.normalisation;
            };
            std::vector<Q> w = vandermonde_weights(radii);
            ASSERT_TRUE(build(w) == k.W) << spec << " in D = " << D;  // the rebuild is faithful
            w[0] += pow(Q(10), -20);
            w[2] -= pow(Q(10), -20);
            k.W = build(w);
            const std::vector<Certificate> cs = certificates(k);
            EXPECT_FALSE(failed(cs, "unit mass")) << spec << " in D = " << D;
            EXPECT_TRUE(failed(cs, "moment |x|^2 = 0")) << spec << " in D = " << D << ": " << failures(cs);
        }
}

// Claiming one more derivative than the kernel has fails a continuity
// certificate (at the edge, or at an inner breakpoint for the cubic spline).
TEST(Certificate, OverclaimedSmoothnessFails) {
    struct Case {
        const char* spec;
        int D;
        const char* breaking;
    };
    const Case cases[] = {
        {"mollifier:M=4", 3, "W^(4) continuous at r = 1"},             // (1-r^2)^4: C^3
        {"mollifier:M=9,order=6", 2, "W^(9) continuous at r = 1"},     // C^8
        {"wendland:k=2", 3, "W^(6) continuous at r = 1"},              // (1-r)^6 p, p(1) != 0: C^5
        {"wendland:k=4,l=4", 1, "W^(13) continuous at r = 1"},         // (1-r)^(0+8+4+1) p: C^12
        {"cubic-spline", 3, "W^(3) continuous at r = 1/2"},            // third derivative jumps 36 -> -12
        {"poly6", 2, "W^(3) continuous at r = 1"},
        {"combo:m=2,base=wendland:k=1", 3, "W^(4) continuous at r = 1/2"},  // (1-2r)^4 p(2r) ends at 1/2
        {"wendland-missing:k=1,l=1", 3, "W^(7) continuous at r = 1"},  // ~ (1-r)^(2+2+1+1+1/2): C^6
        {"wendland-missing:k=2,l=2", 2, "W^(9) continuous at r = 1"},  // ~ (1-r)^(1+4+2+1+1/2): C^8
    };
    for (const Case& c : cases) {
        ExactKernel k = kernel(c.spec, c.D);
        ASSERT_EQ(failures(certificates(k)), "") << c.spec;
        k.claims.smoothness += 1;
        const std::vector<Certificate> cs = certificates(k);
        EXPECT_TRUE(failed(cs, c.breaking)) << c.spec << " in D = " << c.D << ": " << failures(cs);
    }
}

// Over- and under-claimed order.
TEST(Certificate, MisclaimedOrderFails) {
    ExactKernel k = kernel("mollifier:M=9,order=6", 3);
    k.claims.order = 8;
    EXPECT_TRUE(failed(certificates(k), "moment |x|^6 = 0"));
    k.claims.order = 4;
    EXPECT_TRUE(failed(certificates(k), "moment |x|^4 != 0 (order exactly 4)"));
    ExactKernel c = kernel("combo:m=3,base=wendland:k=3,l=2", 2);
    c.claims.order += 2;
    EXPECT_TRUE(failed(certificates(c), "moment |x|^6 = 0"));
}

// Delta phi = W fails when the potential does not belong to the kernel.
TEST(Certificate, ForeignPotentialFails) {
    const ExactKernel k = kernel("wendland:k=2", 3);
    Quantities q = derive_quantities(k);
    q.potential = derive_quantities(kernel("wendland:k=1", 3)).potential;
    EXPECT_TRUE(failed(certify(k, q), "Delta phi = W identically"));
}

}  // namespace
}  // namespace mollify::gen
