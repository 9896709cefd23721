// The emitted tables are faithful: every kernel of generated/ compiles (with
// -Wall -Wextra -Werror), its normalisation is the correctly rounded exact
// constant, and every quantity evaluated straight from the table
// (table::evaluate, the unoptimised reference) matches the exact value at
// sample radii, including the support edge and outside it.
#include "kernel.hpp"
#include "quantities.hpp"
#include "rounding.hpp"

#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <cmath>

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
        const Kernel k = make_kernel(parse_spec(t->spec), t->dim);
        const Quantities q = derive_quantities(k);
        EXPECT_EQ(t->normalisation, round_to_double(k.normalisation)) << t->spec;
        EXPECT_EQ(std::string(t->normalisation_exact), k.normalisation.to_string()) << t->spec;
        EXPECT_EQ(t->has_potential, k.claims.no_potential.empty()) << t->spec;
        for (int i = 0; i < table::quantity_count; ++i) {
            const std::string& name = quantity_names()[static_cast<std::size_t>(i)];
            if (!t->has_potential && name.find("potential") != std::string::npos) {
                EXPECT_EQ(t->quantities[i].npieces, 0);
                continue;
            }
            const Radial& f = quantity(k, q, name);
            std::vector<std::pair<double, double>> values;  // (table, exact)
            double scale = 0;
            for (const Q& r : sample_radii) {
                if (r == 0 && singular_at_zero(f)) continue;
                // The sqrt/arcsech/arcsin closed forms of missing Wendland functions
                // cancel singular terms near r = 0 (e.g. S/r - 1/r); the table's
                // plain form is only checked away from 0 here, the runtime's
                // accuracy there is measured separately (issue 3).
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

TEST(Tables, CatalogueHoldsTheDefaultKernels) {
    std::set<std::string> specs;
    for (const table::Kernel* t : mollify::tables::all_kernels) specs.insert(std::string(t->spec) + "@" + std::to_string(t->dim));
    for (const char* s : {"mollifier:M=9,order=6@3", "wendland:k=4,l=4@2", "combo:m=3,base=wendland:k=3,l=2@1",
                          "combo:m=3,base=mollifier:M=9@3", "poly6@1", "viscosity@2", "box-d2@1", "cubic-spline@3"})
        EXPECT_TRUE(specs.count(s)) << s;
    EXPECT_FALSE(specs.count("viscosity@1"));
}
