// The hard points of a table at which two evaluations of it are compared
// (runtime_forms_test, batch_loops_test).
#pragma once

#include <mollify/table.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace mollify::testing {

// r/h at the hard points of a table: near 0 (down to subnormals), at and
// within ulps of the support's edge, around every breakpoint and
// combination radius, beyond, and `uniform` points uniform in [0, 1.25];
// sorted, no repeats.
inline std::vector<double> hard_q(const table::Kernel& k, int uniform = 1500) {
    std::vector<double> q = {0.0, 4.9e-324, 1e-310, 1e-300, 1e-160, 1e-20, 1e-8, 1e-3, 0.5, 1.0, 1.5, 3.0, 1e3};
    auto around = [&](double x) {
        double up = x, down = x;
        for (int i = 0; i < 3; ++i) {
            up = std::nextafter(up, 2.0);
            down = std::nextafter(down, 0.0);
            q.push_back(up);
            q.push_back(down);
        }
        q.push_back(x);
    };
    around(1.0);
    for (const double e : {1e-15, 1e-12, 1e-9, 1e-6}) q.push_back(1 - e);
    for (int qi = 0; qi < table::quantity_count; ++qi)
        for (int p = 0; p < k.quantities[qi].npieces; ++p) {
            const table::Piece& piece = k.quantities[qi].pieces[p];
            if (piece.lo > 0 && piece.lo <= 1) around(piece.lo);
            for (int t = 0; t < piece.nterms; ++t)
                if (piece.terms[t].edge > 0 && piece.terms[t].edge <= 1) around(piece.terms[t].edge);
        }
    std::mt19937_64 rng(18);
    std::uniform_real_distribution<double> u(0, 1.25);
    for (int i = 0; i < uniform; ++i) q.push_back(u(rng));
    std::sort(q.begin(), q.end());
    q.erase(std::unique(q.begin(), q.end()), q.end());
    return q;
}

}  // namespace mollify::testing
