// The Barnes-Hut treecode with multipole expansions of order p (notes 001,
// "Barnes-Hut treecode: particle-cluster interactions", and "the monopole
// approximation is the 1st term in a multipole expansion ... the accuracy
// is improved using higher-order terms"):
//
//   compute_interaction(x, c):
//     if rho_c / R <= theta  and  R - rho_c >= delta_max(c):   far field of c (multipole.hpp)
//     else if c is a leaf:                                    exact mollified sum over c's sources
//     else:                                                   recurse into the children
//
// with R = |x - centre(c)| and rho_c the cell's radius. The second condition
// is what smoothing adds: every source of an accepted cell is then at least
// its delta away from x, where the mollified potential equals the Green's
// function, so the expansion is an expansion of the exact far field; pairs
// closer than delta are always summed with the exact kernel.
//
// 2D runs this particle-cluster form per target (a complex expansion costs
// O(p) per cell). 3D applies the two tests to PAIRS of cells of a target
// tree and the source tree (a dual traversal; since stop 41 measured to the
// cells' source boxes: the full M2L's ratio below theta/(2 - theta), the
// boxes delta_max apart; accepted()) and collects accepted source cells into Taylor (local)
// expansions about target cells, pushed down to the leaves: one
// translation per cell pair instead of an O(p^3) expansion per target and
// cell, which at p = 8..14 is what makes 3D pay off (Dehnen's method,
// J. Comput. Phys. 179 (2002), with Cartesian expansions). Each translation
// is the full one of the FMM (the local expansion of degree p of the whole
// degree-p multipole expansion, Multipole<3>::add_local), whose error per
// order at the opening angle, ~theta/(2 - theta), is what lets wide angles
// (theta 0.6-0.75) with large leaves (400 sources, TreeOptions::leaf_for)
// reach 1e-5..1e-7 of the field with few translations. A pair well inside
// the opening angle is translated at the lowest degree with the truncation
// factor of the worst balanced pair (Dehnen's error-controlled order;
// Multipole<3>::pair_degree).
//
// Where the 3D time goes and what keeps it down (one thread; shares at
// N = 10^6 neutral, theta 0.7, p = 17, measured by perf 2026-11-29):
// - Near field (descend), ~45 % then, ~70 % since (the Intel host,
//   N = 10^5 | 10^6, theta 0.72 | 0.7, p = 14 | 16, 2026-12-04): per target
//   leaf the near cells' sources are gathered into runs; every pair beyond
//   its support gets the Green's function in one vectorised pass
//   (detail::add_green), which lists the pairs it leaves out, those within
//   a support, for the exact kernel (detail::within_kernel, one batch per
//   target; 8 | 6 %); the two parts split the pairs exactly, so each pair
//   is counted once. At the sources, a leaf pair found from both sides
//   gets one Green's pass for both directions (detail::add_green_mutual,
//   four targets at a time where 1/sqrt is refined, Treecode::tile;
//   54 | 58 %), and so do a leaf's own pairs, j > i (7 | 6 %). On Intel's
//   AVX-512 cores 1/sqrt is refined from its estimate (the divider there
//   held the pass at ~60 % of the time), elsewhere each block's square
//   roots and divisions are issued a block ahead (detail::green_pass).
//   With a global delta one kernel value serves both ends of a pair within
//   a support. Each target's sums go to a per-thread array in tree order,
//   permuted to the caller's order once. Until stop 62 the pairs within a
//   support were searched for in a second pass over the cells that come
//   within delta_max of the target (13 % with its kernel), the own leaf
//   went one way, and the passes ended in scalar tails.
// - M2L (translate), ~26 % with the Cartesian translation ((p + 1)^4
//   multiply-adds a pair after the harmonic reduction), 6-12 % since it
//   rotates real spherical harmonics (Multipole<3>::add_local: ~2 (p + 1)^3;
//   the Intel host, N = 10^5, theta 0.7-0.72, p = 14-19, 2026-12-04), a
//   target cell's source cells eight at a time, one per SIMD lane.
// - P2M, M2M, L2L, L2P, ~9 %: sources (targets) eight at a time, each
//   monomial one multiplication from its parent's; the moments of a cell
//   that is not a leaf and the local expansion of a child by a change of
//   centre one axis at a time (O(p^4), not the O(p^6) double sum; upper
//   cells' moments were summed from all their sources before, 9 % of the
//   time then). Local expansions live per depth while their subtree is
//   descended (no array of every cell's).
//
//   mollify::poisson::Treecode<3, mollify::Kernel> tree(k, sources, {.theta = 0.5, .order = 6});
//   auto f = tree.evaluate(targets);    // or tree.evaluate() at the sources
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>
#include <mollify/poisson/multipole.hpp>
#include <mollify/poisson/pair_sum.hpp>
#include <mollify/poisson/sources.hpp>
#include <mollify/poisson/tolerance.hpp>
#include <mollify/poisson/tree.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

template <int D, RadialKernel K>
class Treecode {
public:
    Treecode(const K& kernel, const Sources<D>& sources, const TreeOptions& options)
        : kernel_(kernel), options_(checked(options)), expansion_(options.order),
          tree_((detail::check_kernel(kernel, D), detail::check_sources(sources), sources.x), sources.delta,
                options_.leaf_size),
          s_(sources, tree_.order()) {
        moments();
    }

    const Tree<D>& tree() const { return tree_; }
    const TreeOptions& options() const { return options_; }

    // phi and E = -grad phi at the targets.
    Field<D> evaluate(const Points<D>& targets) const {
        const std::size_t m = detail::check_targets<D>(targets);
        Field<D> out(m);
        if (m == 0) return out;
        if constexpr (D == 3) {
            const std::array<double, 1> no_delta{1.0};
            const Tree<D> t(targets, no_delta, options_.leaf_size);
            std::array<std::vector<double>, D> y;
            for (int c = 0; c < D; ++c) {
                y[c].resize(m);
                for (std::size_t i = 0; i < m; ++i) y[c][i] = targets[c][t.order()[i]];
            }
            by_target_leaf(t, y, out);
        } else {
            by_target(m, [&](std::size_t i) { return i; }, [&](std::size_t i, int c) { return targets[c][i]; }, out);
        }
        return out;
    }

    // At the sources themselves (self terms exact).
    Field<D> evaluate() const {
        Field<D> out(s_.size());
        if constexpr (D == 3) {
            by_target_leaf(tree_, s_.x, out);
        } else {
            const auto& order = tree_.order();
            by_target(s_.size(), [&](std::size_t i) { return order[i]; }, [&](std::size_t i, int c) { return s_.x[c][i]; }, out);
        }
        return out;
    }

private:
    // The options as used: checked, the leaf size resolved (leaf_for).
    static TreeOptions checked(TreeOptions o) {
        o.check();
        o.leaf_size = o.leaf_for(D);
        return o;
    }

    // Moments of every cell. 2D: from its own sources (each source enters one
    // cell per level: O(N log N) work, parallel over cells). 3D: the leaves'
    // from their sources, every other cell's from its children's
    // (Multipole<3>::add_child_moments, exact), each cell's full moments kept
    // only until its parent has them; stored as their harmonic reduction
    // (Multipole<3>::reduce). At N = 10^6, p = 17: 4 % of the time instead
    // of 9 % from every source at every level.
    void moments() {
        const auto& cells = tree_.cells();
        m_.assign(cells.size() * stride(), 0.0);
        if constexpr (D == 3) {
            const std::size_t n = expansion_.size();
            // The subtrees of the task cells in parallel, then the cells above them.
            const std::vector<int> tasks = task_cells(tree_);
            std::vector<double> top(tasks.size() * n);
            std::vector<int> slot(cells.size(), -1);
            for (std::size_t i = 0; i < tasks.size(); ++i) slot[static_cast<std::size_t>(tasks[i])] = static_cast<int>(i);
            const auto count = static_cast<long>(tasks.size());
            MOLLIFY_PARALLEL_FOR(schedule(dynamic, 1))
            for (long ti = 0; ti < count; ++ti) {
                std::vector<std::vector<double>> scratch;
                std::vector<double> work;
                const auto i = static_cast<std::size_t>(ti);
                full_moments(tasks[i], top.data() + i * n, scratch, 0, work, {}, top.data());
            }
            if (slot[0] < 0) {
                std::vector<std::vector<double>> scratch;
                std::vector<double> root(n), work;
                full_moments(0, root.data(), scratch, 0, work, slot, top.data());
            }
        } else {
            const auto count = static_cast<long>(cells.size());
            MOLLIFY_PARALLEL_FOR(schedule(dynamic, 8))
            for (long ci = 0; ci < count; ++ci) {
                const Cell<D>& c = cells[static_cast<std::size_t>(ci)];
                double* m = m_.data() + static_cast<std::size_t>(ci) * stride();
                for (std::size_t j = c.begin; j < c.end; ++j) {
                    std::array<double, D> y;
                    for (int k = 0; k < D; ++k) y[k] = s_.x[k][j];
                    expansion_.add_source(m, y, c.centre, scale(c), s_.q[j]);
                }
            }
        }
    }

    // The full moments of cell ci into out (size()), and the reduced ones of
    // every cell of its subtree into m_; a cell with a slot (task cells, done
    // first) has its full moments in top. scratch: a buffer per depth.
    void full_moments(int ci, double* out, std::vector<std::vector<double>>& scratch, std::size_t depth,
                      std::vector<double>& work, const std::vector<int>& slot, const double* top) {
        const Cell<D>& c = tree_.cells()[static_cast<std::size_t>(ci)];
        const std::size_t n = expansion_.size();
        if (!slot.empty() && slot[static_cast<std::size_t>(ci)] >= 0) {
            const double* m = top + static_cast<std::size_t>(slot[static_cast<std::size_t>(ci)]) * n;
            std::copy(m, m + n, out);
            return;
        }
        std::fill(out, out + n, 0.0);
        if (c.leaf()) {
            expansion_.add_sources(out, {s_.x[0].data() + c.begin, s_.x[1].data() + c.begin, s_.x[2].data() + c.begin},
                                   s_.q.data() + c.begin, c.end - c.begin, c.centre, scale(c), work);
        } else {
            if (scratch.size() <= depth) scratch.emplace_back(n);  // moving a vector keeps its buffer
            double* child = scratch[depth].data();
            for (int k = 0; k < c.children; ++k) {
                const Cell<D>& C = tree_.cells()[static_cast<std::size_t>(c.first_child + k)];
                full_moments(c.first_child + k, child, scratch, depth + 1, work, slot, top);
                expansion_.add_child_moments(child, scale(C), C.centre, out, scale(c), c.centre, work);
            }
        }
        expansion_.reduce(out, c.radius > 0 ? options_.order : 0, m_.data() + static_cast<std::size_t>(ci) * stride(), work);
    }

    // The target cells of the first level with at least 64 of them (or the
    // leaves above it): independent tasks for the threads.
    static std::vector<int> task_cells(const Tree<D>& t) {
        const auto& tc = t.cells();
        std::vector<int> tasks{0};
        while (tasks.size() < 64) {
            std::vector<int> next;
            bool split = false;
            for (const int ci : tasks) {
                const Cell<D>& c = tc[static_cast<std::size_t>(ci)];
                if (c.leaf()) {
                    next.push_back(ci);
                } else {
                    split = true;
                    for (int k = 0; k < c.children; ++k) next.push_back(c.first_child + k);
                }
            }
            tasks.swap(next);
            if (!split) break;
        }
        return tasks;
    }

    // Coefficients per cell in m_: reduced in 3D.
    std::size_t stride() const {
        if constexpr (D == 3) return expansion_.reduced_size(); else return expansion_.size();
    }

    static double scale(const Cell<D>& c) { return c.radius > 0 ? c.radius : 1.0; }

    // 2D: compute_interaction(x_i, root) for every target (particle-cluster).
    template <class Index, class Coordinate>
    void by_target(std::size_t m, Index index, Coordinate coordinate, Field<D>& out) const {
        const auto count = static_cast<long>(m);
        MOLLIFY_PARALLEL_FOR(schedule(dynamic, 64))
        for (long ii = 0; ii < count; ++ii) {
            const auto i = static_cast<std::size_t>(ii);
            std::array<double, D> x, e{};
            for (int c = 0; c < D; ++c) x[c] = coordinate(i, c);
            double phi = 0;
            at(x, phi, e);
            const std::size_t o = index(i);
            out.potential[o] = phi;
            for (int c = 0; c < D; ++c) out.field[c][o] = e[c];
        }
    }

    // 3D: the notes' test applied to PAIRS of cells (a dual traversal of a
    // target tree t and the source tree; targets y in t's order). A pair
    // passing (rho_s + rho_t) / R < theta and R - rho_s - rho_t >= delta_max
    // enters the target cell's local expansion (Multipole<3>::add_local),
    // pushed down to the leaves (add_shifted) and evaluated at each target;
    // a pair of leaves that does not pass is summed exactly. Otherwise the
    // larger cell is split. Target subtrees are independent tasks (OpenMP).
    void by_target_leaf(const Tree<D>& t, const std::array<std::vector<double>, D>& y, Field<D>& out) const {
        const auto& tc = t.cells();
        const std::size_t n = expansion_.size();
        std::vector<char> has_local(tc.size(), 0);
        std::vector<std::vector<int>> near(tc.size());
        std::vector<std::vector<Far>> far(tc.size());
        const std::vector<int> tasks = task_cells(t);
        const auto count = static_cast<long>(tasks.size());
        MOLLIFY_PARALLEL_FOR(schedule(dynamic, 1))
        for (long ti = 0; ti < count; ++ti) interact(t, tasks[static_cast<std::size_t>(ti)], 0, far, has_local, near);
        // The near field's Green's-function part, at the sources (t is the
        // source tree): a leaf pair (a, b) found from both sides is summed
        // once, at the smaller index, for both directions (add_green_mutual),
        // as a leaf's own pairs (j > i); the other near cells one way.
        NearField nf;
        nf.mutual = &t == &tree_;
        nf.green.resize(tc.size());
        nf.both.resize(tc.size());
        if (nf.mutual) {  // phi_delta(0) (per-source deltas: phi_1(0)), each source's own share
            const double zero = 0;
            detail::batch<QuantityId::potential>(kernel_, &zero, &nf.self_pot, 1, s_.smoothing);
        }
        const auto ncells = static_cast<long>(tc.size());
        if (nf.mutual) {
            MOLLIFY_PARALLEL_FOR(schedule(static))
            for (long ci = 0; ci < ncells; ++ci) std::sort(near[static_cast<std::size_t>(ci)].begin(), near[static_cast<std::size_t>(ci)].end());
            nf.acc.resize(static_cast<std::size_t>(mollify::detail::thread_count()));
        }
        MOLLIFY_PARALLEL_FOR(schedule(static))
        for (long ci = 0; ci < ncells; ++ci) {
            const auto a = static_cast<std::size_t>(ci);
            for (const int b : near[a]) {
                const auto& back = near[static_cast<std::size_t>(b)];
                if (nf.mutual && b == ci) continue;  // the leaf's own pairs: descend, j > i both ways
                if (!nf.mutual || !std::binary_search(back.begin(), back.end(), static_cast<int>(ci)))
                    nf.green[a].push_back(b);
                else if (b > ci)
                    nf.both[a].push_back(b);
            }
        }
        MOLLIFY_PARALLEL_FOR(schedule(dynamic, 1))
        for (long ti = 0; ti < count; ++ti) {
            // A local expansion per depth: a cell's lives only while its
            // subtree is descended (no array of every cell's to allocate).
            // No ancestor of a task has far pairs (interact starts at the tasks).
            std::vector<std::vector<double>> local(1, std::vector<double>(n, 0.0));
            std::vector<double> work;
            descend(t, tasks[static_cast<std::size_t>(ti)], y, far, local, 0, has_local, nf, out, work);
        }
        if (nf.mutual) {
            const auto m = static_cast<long>(s_.size());
            MOLLIFY_PARALLEL_FOR(schedule(static))
            for (long ii = 0; ii < m; ++ii) {
                const auto i = static_cast<std::size_t>(ii);
                std::array<double, 4> sum{};
                for (const auto& acc : nf.acc)
                    if (!acc[0].empty())
                        for (std::size_t c = 0; c < 4; ++c) sum[c] += acc[c][i];
                const std::size_t o = t.order()[i];
                out.potential[o] = sum[0];
                for (int c = 0; c < D; ++c) out.field[c][o] = sum[static_cast<std::size_t>(c) + 1];
            }
        }
    }

    // The near field's split (by_target_leaf) and, at the sources (mutual),
    // per thread the potential and field of each source in tree order: its
    // own sums as a target and what targets in other leaves give it.
    struct NearField {
        bool mutual = false;
        double self_pot = 0;  // phi_delta(0), or phi_1(0) with per-source deltas (mutual)
        std::vector<std::vector<int>> green, both;
        std::vector<std::array<std::vector<double>, 4>> acc;
    };

    static double local_scale(const Cell<D>& c) { return c.half > 0 ? c.half * std::sqrt(double(D)) : 1.0; }

    // An accepted pair: source cell b at M2L degree `degree`.
    struct Far {
        int b, degree;
    };

    // The 3D pair test: the ratio of the full M2L measured to the cells'
    // source boxes, not to spheres about their centres: rho_s over the
    // distance from B's centre to A's box, rho_t over that from A's centre
    // to B's box, accepted below theta/(2 - theta) (what two spheres at the
    // opening angle have), and every pair beyond its support when the boxes
    // are delta_max apart. A 244-source leaf then keeps ~33 near leaves
    // instead of ~57 at theta 0.7 (the leaves two apart in one axis and one
    // in another are accepted): N = 10^6 neutral, 1e-5 in 5.6 instead of
    // 6.7 CPU s. The spheres' ratio (rho_s + rho_t)/|R|, the rate of the
    // double series the translation truncates, is kept below (1 + theta)/2:
    // without that bound unbalanced pairs of a Gaussian blob left an error
    // floor (4.5e-7 at theta 0.7 for p = 16..20; 1.2e-8 at p = 20 with it;
    // the uniform sets have no such pairs). The pair's ratio c
    // (Multipole<3>::pair_degree) if it is accepted.
    std::optional<double> accepted(const Cell<D>& A, const Cell<D>& B) const {
        double r2 = 0, ds2 = 0, dt2 = 0, gap2 = 0;
        for (int k = 0; k < D; ++k) {
            const double R = A.centre[k] - B.centre[k];
            const double s = std::max({A.lo[k] - B.centre[k], B.centre[k] - A.hi[k], 0.0});
            const double t = std::max({B.lo[k] - A.centre[k], A.centre[k] - B.hi[k], 0.0});
            const double g = std::max({A.lo[k] - B.hi[k], B.lo[k] - A.hi[k], 0.0});
            r2 += R * R;
            ds2 += s * s;
            dt2 += t * t;
            gap2 += g * g;
        }
        const double theta = options_.theta;
        if (!(ds2 > 0 && dt2 > 0 && gap2 >= B.delta_max * B.delta_max)) return std::nullopt;
        if (!(A.radius + B.radius < 0.5 * (1 + theta) * std::sqrt(r2))) return std::nullopt;
        const double c = std::max(B.radius / std::sqrt(ds2), A.radius / std::sqrt(dt2));
        if (!(c < theta / (2 - theta))) return std::nullopt;
        return c;
    }

    void interact(const Tree<D>& t, int a, int b, std::vector<std::vector<Far>>& far, std::vector<char>& has_local,
                  std::vector<std::vector<int>>& near) const {
        const Cell<D>& A = t.cells()[static_cast<std::size_t>(a)];
        const Cell<D>& B = tree_.cells()[static_cast<std::size_t>(b)];
        if (const auto c = accepted(A, B)) {
            far[static_cast<std::size_t>(a)].push_back({b, expansion_.pair_degree(*c, options_.theta)});
            has_local[static_cast<std::size_t>(a)] = 1;
        } else if (A.leaf() && B.leaf()) {
            near[static_cast<std::size_t>(a)].push_back(b);
        } else if (B.leaf() || (!A.leaf() && A.radius >= B.radius)) {
            for (int k = 0; k < A.children; ++k) interact(t, A.first_child + k, b, far, has_local, near);
        } else {
            for (int k = 0; k < B.children; ++k) interact(t, a, B.first_child + k, far, has_local, near);
        }
    }

    // Local expansions down to the leaves, then phi and E at each target.
    // The accepted pairs of target cell a, M2L in batches of
    // Multipole<3>::lanes source cells of similar degree, into la.
    void translate(const Cell<D>& A, std::vector<Far>& list, double* la, std::vector<double>& work) const {
        if constexpr (D == 3) {
            if (list.empty()) return;
            constexpr int W = Multipole<3>::lanes;
            std::sort(list.begin(), list.end(),
                      [](const Far& x, const Far& z) { return x.degree != z.degree ? x.degree < z.degree : x.b < z.b; });
            thread_local std::vector<double> lanes;  // per-lane sums of the reduced coefficients
            lanes.assign((stride() + 1) * W, 0.0);
            double* reduced = Multipole<3>::aligned(lanes.data());
            std::array<Multipole<3>::Source, W> batch;
            const double rho_t = local_scale(A);
            for (std::size_t i0 = 0; i0 < list.size(); i0 += W) {
                const int count = static_cast<int>(std::min<std::size_t>(W, list.size() - i0));
                for (int l = 0; l < count; ++l) {
                    const int b = list[i0 + static_cast<std::size_t>(l)].b;
                    const Cell<D>& B = tree_.cells()[static_cast<std::size_t>(b)];
                    batch[static_cast<std::size_t>(l)] = {m_.data() + static_cast<std::size_t>(b) * stride(), scale(B),
                                                          {A.centre[0] - B.centre[0], A.centre[1] - B.centre[1],
                                                           A.centre[2] - B.centre[2]}};
                }
                expansion_.add_local(batch.data(), count, rho_t, reduced, work,
                                     list[i0 + static_cast<std::size_t>(count) - 1].degree);
            }
            expansion_.add_expanded(reduced, la, work);
        }
    }

    void descend(const Tree<D>& t, int a, const std::array<std::vector<double>, D>& y,
                 std::vector<std::vector<Far>>& far, std::vector<std::vector<double>>& local, std::size_t depth,
                 std::vector<char>& has_local, NearField& nf,
                 Field<D>& out, std::vector<double>& work) const {
        const Cell<D>& A = t.cells()[static_cast<std::size_t>(a)];
        const std::size_t n = expansion_.size();
        double* la = local[depth].data();  // the parent's part already in
        translate(A, far[static_cast<std::size_t>(a)], la, work);
        if (!A.leaf()) {
            if (local.size() <= depth + 1) {
                local.emplace_back(n);  // moving a vector keeps its buffer: la stays valid
            }
            double* lc = local[depth + 1].data();
            for (int k = 0; k < A.children; ++k) {
                const int c = A.first_child + k;
                std::fill(lc, lc + n, 0.0);
                if (has_local[static_cast<std::size_t>(a)]) {
                    const Cell<D>& C = t.cells()[static_cast<std::size_t>(c)];
                    if constexpr (D == 3)
                        expansion_.add_shifted(la, local_scale(A), A.centre, local_scale(C), C.centre, lc, work);
                    has_local[static_cast<std::size_t>(c)] = 1;
                }
                descend(t, c, y, far, local, depth + 1, has_local, nf, out, work);
            }
            return;
        }
        // The near field: the sources of the leaf's near cells gathered
        // into runs (adjacent cells merged), the Green's function for every
        // pair beyond its support in one vectorised pass per target and run
        // (detail::add_green; detail::add_green_mutual for the cells summed
        // both ways here), which lists the pairs within a support for the
        // exact kernel (detail::within_kernel), one batch per target.
        const auto& cells = tree_.cells();
        Gathered& g = gathered();
        g.one.gather(cells, s_, nf.green[static_cast<std::size_t>(a)]);
        g.both.gather(cells, s_, nf.both[static_cast<std::size_t>(a)]);
        g.own.gather(cells, s_, nf.mutual ? std::vector<int>{a} : std::vector<int>{});
        g.room();
        const std::size_t na = A.end - A.begin;
        g.phi.assign(na, 0.0);
        for (auto& c : g.e) c.assign(na, 0.0);
        // At the sources: what the leaf's targets get and give the mutual
        // cells' sources (tree order, per thread).
        std::array<std::vector<double>, 4>* acc = nullptr;
        if (nf.mutual) {
            acc = &nf.acc[static_cast<std::size_t>(mollify::detail::thread_index())];
            if ((*acc)[0].empty())
                for (auto& v : *acc) v.assign(s_.size(), 0.0);
        }
        if constexpr (D == 3)
            if (has_local[static_cast<std::size_t>(a)])
                expansion_.add_local_at(la, local_scale(A), A.centre, {y[0].data() + A.begin, y[1].data() + A.begin, y[2].data() + A.begin},
                                        na, g.phi.data(), {g.e[0].data(), g.e[1].data(), g.e[2].data()}, work);
        constexpr double k = 0.25 * std::numbers::inv_pi;
        const bool per_source = !s_.global;
        const bool tiled = detail::fastest_inverse_sqrt() == detail::InverseSqrt::refine;
        // The leaf's targets a tile at a time: the mutual cells' Green's pass
        // for the tile's targets together (detail::add_green_mutual over
        // Targets<tile>), then each target's other parts in order.
        for (std::size_t i0 = A.begin; i0 < A.end; i0 += tile) {
            const std::size_t tn = std::min<std::size_t>(tile, A.end - i0);
            std::array<double, tile> both_phi{};
            std::array<std::array<double, 3>, tile> both_e{};
            std::array<detail::WithinPairs, tile> both, back;
            for (std::size_t u = 0; u < tile; ++u) {
                both[u] = {g.slot[u].both_at.data(), g.slot[u].both_r2.data()};
                back[u] = {g.slot[u].back_at.data(), g.slot[u].back_r2.data()};
            }
            if constexpr (D == 3)
                if (!g.both.q.empty()) {
                    if (tn == tile && tiled)
                        both_pass<tile>(i0, 0, y, both, back, both_phi, both_e);
                    else
                        for (std::size_t u = 0; u < tn; ++u) both_pass<1>(i0 + u, u, y, both, back, both_phi, both_e);
                }
            for (std::size_t u = 0; u < tn; ++u) {
                const std::size_t i = i0 + u, l = i - A.begin;  // the target's place in the leaf
                std::array<double, D> x, e;
                for (int c = 0; c < D; ++c) {
                    x[c] = y[c][i];
                    e[c] = g.e[static_cast<std::size_t>(c)][l];
                }
                double phi = g.phi[l];
                if constexpr (D == 3) {
                    phi += both_phi[u];
                    for (std::size_t c = 0; c < D; ++c) e[c] += both_e[u][c];
                    Lists lists{{g.one.within_at.data(), g.one.within_r2.data()},
                                both[u],
                                back[u],
                                {g.own.within_at.data(), g.own.within_r2.data()},
                                {g.own_back_at.data(), g.own_back_r2.data()}};
                    detail::add_green(g.one.x[0].data(), g.one.x[1].data(), g.one.x[2].data(), g.one.q.data(),
                                      g.one.d2.data(), g.one.q.size(), x, phi, e, lists.one);
                    if (nf.mutual) {
                        // The leaf's own sources j > i (at l + 1 on); what the
                        // sources j < i gave i through theirs, scaled as the
                        // mutual cells' sums below.
                        const std::size_t o = l + 1;
                        phi -= k * g.own.w[0][l];
                        for (std::size_t c = 0; c < D; ++c) e[c] -= k * g.own.w[c + 1][l];
                        detail::add_green_mutual(g.own.x[0].data() + o, g.own.x[1].data() + o, g.own.x[2].data() + o,
                                                 g.own.q.data() + o, g.own.d2.data() + o, g.own.q.size() - o, x, s_.q[i],
                                                 s_.delta[i] * s_.delta[i], phi, e, g.own.w[0].data() + o,
                                                 g.own.w[1].data() + o, g.own.w[2].data() + o, g.own.w[3].data() + o,
                                                 lists.own, per_source ? &lists.own_back : nullptr);
                    }
                    within(nf, A, i, x, lists, phi, e, acc);
                }
                if (acc) {  // in tree order, sequential; by_target_leaf permutes once
                    (*acc)[0][i] += phi;
                    for (std::size_t c = 0; c < D; ++c) (*acc)[c + 1][i] += e[c];
                } else {
                    const std::size_t o = t.order()[i];
                    out.potential[o] = phi;
                    for (int c = 0; c < D; ++c) out.field[c][o] = e[c];
                }
            }
        }
        if (!g.both.q.empty()) {
            // The Green's pass's sums for the mutual cells' sources, scaled
            // (phi = -q/(4 pi r), E = -q (x_j - x_t)/(4 pi r^3)).
            for (const auto& [begin, end, at] : g.both.runs)
                for (std::size_t j = begin; j < end; ++j)
                    for (std::size_t c = 0; c < 4; ++c) (*acc)[c][j] -= k * g.both.w[c][at + j - begin];
        }
    }

    // Targets per mutual cells' pass (detail::Targets): each block of
    // sources loaded and its sums stored once for four. One pass over 256 to
    // 16,384 sources took 0.93-1.05 ns a pair with one target, 0.77-0.84
    // with two, 0.72-0.79 with four (more spill registers); the treecode at
    // N = 10^6 neutral, theta 0.7, p = 16, 4.67-4.84 -> 4.49-4.59 s (the
    // Intel Xeon of stop 62, alternating runs). Only where 1/sqrt is refined
    // (InverseSqrt::refine): with the division two or four targets a pass
    // were 8-10 % slower on the AMD Zen 5 host of stop 42, bound by the
    // divider, so there the targets go one at a time, as before.
    static constexpr std::size_t tile = 4;

    // The mutual cells' Green's pass (Gathered::both) for the T targets from
    // i0 (slot u0 on): their sums to phi and e, their lists to both and back.
    template <std::size_t T>
    void both_pass(std::size_t i0, std::size_t u0, const std::array<std::vector<double>, D>& y,
                   std::array<detail::WithinPairs, tile>& both, std::array<detail::WithinPairs, tile>& back,
                   std::array<double, tile>& phi, std::array<std::array<double, 3>, tile>& e) const {
        Run& r = gathered().both;
        detail::Targets<static_cast<int>(T)> tg;
        for (std::size_t u = 0; u < T; ++u) {
            const std::size_t i = i0 + u;
            for (std::size_t c = 0; c < 3; ++c) tg.x[u][c] = y[c][i];
            tg.q[u] = s_.q[i];
            tg.d2[u] = s_.delta[i] * s_.delta[i];
            tg.to_target[u] = &both[u0 + u];
            tg.to_source[u] = s_.global ? nullptr : &back[u0 + u];
        }
        detail::add_green_mutual<static_cast<int>(T)>(r.x[0].data(), r.x[1].data(), r.x[2].data(), r.q.data(),
                                                      r.d2.data(), r.q.size(), tg, r.w[0].data(), r.w[1].data(),
                                                      r.w[2].data(), r.w[3].data());
        for (std::size_t u = 0; u < T; ++u) {
            phi[u0 + u] = tg.phi[u];
            e[u0 + u] = tg.e[u];
        }
    }

    // A target's pairs within a support, as its Green's passes list them:
    // one (the one-way cells), both and back (the mutual cells: within the
    // source's support, the target's where it differs), own and own_back
    // (the leaf's own sources j > i, from i + 1 on).
    struct Lists {
        detail::WithinPairs one, both, back, own, own_back;
    };

    // Who feels a pair's values: the target, the source (a mutual cell's in
    // acc, the leaf's own in Gathered's phi and e), or both.
    enum Share : char { to_target, with_own, with_cells, to_own, to_cells };

    // The pairs of target i (of leaf A) within a support with the exact
    // kernel, in one batch. A global delta's values serve both ends of a
    // pair (Newton's third law); per-source deltas give each direction its
    // own: the source's for i, i's for the mutual cells' and the leaf's
    // sources (back, own_back). i itself gets q_i phi_delta(0).
    void within(const NearField& nf, const Cell<D>& A, std::size_t i, const std::array<double, D>& x,
                const Lists& lists, double& phi, std::array<double, D>& e,
                std::array<std::vector<double>, 4>* acc) const {
        Gathered& g = gathered();
        std::size_t m = 0;
        // A list's pairs but those with the padding (at >= real: Run).
        auto put = [&](const detail::WithinPairs& list, std::size_t real, auto&& source_of, bool by_target, Share share) {
            for (std::size_t k = 0; k < list.size; ++k) {
                if (list.at[k] >= real) continue;
                const std::size_t j = source_of(list.at[k]);
                g.pair_j[m] = j;
                g.pair_r2[m] = list.r2[k];
                g.pair_by[m] = by_target ? i : j;
                g.pair_share[m] = share;
                ++m;
            }
        };
        const auto one = [&](unsigned at) { return g.one.source[at]; };
        const auto both = [&](unsigned at) { return g.both.source[at]; };
        const auto own = [&](unsigned at) { return i + 1 + at; };
        const bool global = s_.global;
        const std::size_t own_real = A.end - i - 1;
        put(lists.one, g.one.size, one, false, to_target);
        put(lists.both, g.both.size, both, false, global ? with_cells : to_target);
        put(lists.back, g.both.size, both, true, to_cells);
        put(lists.own, own_real, own, false, global ? with_own : to_target);
        put(lists.own_back, own_real, own, true, to_own);
        if (nf.mutual)
            phi += s_.q[i] * (global ? nf.self_pot : nf.self_pot * s_.phi_scale[i] + s_.phi_shift[i]);
        const double qt = s_.q[i];
        detail::within_kernel<D>(kernel_, s_, g.pair_r2.data(), g.pair_by.data(), m, [&](std::size_t k, double pot, double gr) {
            const std::size_t j = g.pair_j[k];
            const auto share = static_cast<Share>(g.pair_share[k]);
            std::array<double, D> d;
            for (int c = 0; c < D; ++c) d[c] = x[c] - s_.x[c][j];
            if (share == to_target || share == with_own || share == with_cells) {
                phi += s_.q[j] * pot;
                for (int c = 0; c < D; ++c) e[c] -= s_.q[j] * gr * d[c];
            }
            if (share == with_own || share == to_own) {
                g.phi[j - A.begin] += qt * pot;
                for (std::size_t c = 0; c < D; ++c) g.e[c][j - A.begin] += qt * gr * d[c];
            } else if (share == with_cells || share == to_cells) {
                (*acc)[0][j] += qt * pot;
                for (std::size_t c = 0; c < D; ++c) (*acc)[c + 1][j] += qt * gr * d[c];
            }
        });
    }

    // Sources gathered from a list of cells into plain arrays, adjacent
    // cells (in the source order) as one run; w: the sources' own sums
    // (mutual pairs), zeroed. The arrays are padded to a multiple of eight
    // with sources that add nothing (q = 0; delta^2 = inf: no target is
    // beyond their support, and a pair with them that is listed within is
    // dropped, Treecode::within), so that a Green's pass over them, or over
    // the own leaf's sources from j on, ends on a whole register: the
    // scalar tail's square roots and divisions were ~5 % of the passes' time,
    // 3.5 sources a target on average in the own leaf's.
    struct Run {
        std::array<std::vector<double>, 3> x;
        std::vector<double> q, d2;
        std::array<std::vector<double>, 4> w;
        std::vector<std::array<std::size_t, 3>> runs;  // begin, end, position
        std::vector<std::size_t> source;                 // each position's source
        std::vector<unsigned> within_at;                 // a target's pairs within a support (detail::WithinPairs)
        std::vector<double> within_r2;
        std::size_t size = 0;  // without the padding
        void gather(const std::vector<Cell<D>>& cells, const detail::SourceArrays<D>& s, std::vector<int> list) {
            std::sort(list.begin(), list.end(), [&](int u, int v) {
                return cells[static_cast<std::size_t>(u)].begin < cells[static_cast<std::size_t>(v)].begin;
            });
            std::size_t total = 0;
            for (const int ci : list) total += cells[static_cast<std::size_t>(ci)].end - cells[static_cast<std::size_t>(ci)].begin;
            size = total;
            const std::size_t padded = (total + 7) / 8 * 8;
            const auto pad = [&](std::vector<double>& v, double value) {  // the real part is copied below
                v.resize(padded);
                std::fill(v.begin() + static_cast<std::ptrdiff_t>(total), v.end(), value);
            };
            for (auto& c : x) pad(c, 0.0);
            pad(q, 0.0);
            pad(d2, std::numeric_limits<double>::infinity());
            source.resize(padded);
            within_at.resize(padded);
            within_r2.resize(padded);
            for (auto& c : w) c.assign(padded, 0.0);
            runs.clear();
            std::size_t at = 0;
            for (std::size_t r = 0; r < list.size();) {
                const std::size_t begin = cells[static_cast<std::size_t>(list[r])].begin;
                std::size_t end = cells[static_cast<std::size_t>(list[r])].end;
                for (++r; r < list.size() && cells[static_cast<std::size_t>(list[r])].begin == end; ++r)
                    end = cells[static_cast<std::size_t>(list[r])].end;
                for (int k = 0; k < D; ++k)
                    std::copy(s.x[k].begin() + static_cast<std::ptrdiff_t>(begin), s.x[k].begin() + static_cast<std::ptrdiff_t>(end),
                              x[static_cast<std::size_t>(k)].begin() + static_cast<std::ptrdiff_t>(at));
                std::copy(s.q.begin() + static_cast<std::ptrdiff_t>(begin), s.q.begin() + static_cast<std::ptrdiff_t>(end),
                          q.begin() + static_cast<std::ptrdiff_t>(at));
                for (std::size_t j = begin; j < end; ++j) {
                    d2[at + j - begin] = s.delta[j] * s.delta[j];
                    source[at + j - begin] = j;
                }
                runs.push_back({begin, end, at});
                at += end - begin;
            }
        }
    };

    // The near field of one target leaf (per thread).
    struct Gathered {
        Run one, both, own;  // own: the leaf's own sources (at the sources)
        // The leaf's targets: phi and E from the local expansion.
        std::vector<double> phi;
        std::array<std::vector<double>, 3> e;
        // The pairs within the target's support that the mutual cells'
        // sources feel (a per-source delta: detail::add_green_mutual's
        // to_source), and all of a target's pairs for the kernel's batch.
        struct Slot {  // a tile's target's lists from the mutual cells' pass
            std::vector<unsigned> both_at, back_at;
            std::vector<double> both_r2, back_r2;
        };
        std::array<Slot, tile> slot;
        std::vector<unsigned> own_back_at;
        std::vector<double> own_back_r2;
        std::vector<std::size_t> pair_j, pair_by;
        std::vector<double> pair_r2;
        std::vector<char> pair_share;
        void room() {
            for (Slot& u : slot) {
                u.both_at.resize(both.q.size());
                u.both_r2.resize(both.q.size());
                u.back_at.resize(both.q.size());
                u.back_r2.resize(both.q.size());
            }
            own_back_at.resize(own.q.size());
            own_back_r2.resize(own.q.size());
            const std::size_t most = one.q.size() + 2 * both.q.size() + 2 * own.q.size();
            pair_j.resize(most);
            pair_by.resize(most);
            pair_r2.resize(most);
            pair_share.resize(most);
        }
    };
    static Gathered& gathered() {
        thread_local Gathered g;
        return g;
    }

    // compute_interaction(x, root) of the notes, with an explicit stack.
    void at(const std::array<double, D>& x, double& phi, std::array<double, D>& e) const {
        thread_local std::vector<double> work;
        thread_local std::vector<int> stack;
        const auto& cells = tree_.cells();
        const std::size_t n = expansion_.size();
        stack.assign(1, 0);
        while (!stack.empty()) {
            const int ci = stack.back();
            stack.pop_back();
            const Cell<D>& c = cells[static_cast<std::size_t>(ci)];
            std::array<double, D> R;
            double r2 = 0;
            for (int k = 0; k < D; ++k) {
                R[k] = x[k] - c.centre[k];
                r2 += R[k] * R[k];
            }
            const double r = std::sqrt(r2);
            if (c.radius < options_.theta * r && r - c.radius >= c.delta_max) {
                const int order = c.radius > 0 ? options_.order : 0;
                expansion_.add_far(m_.data() + static_cast<std::size_t>(ci) * n, scale(c), order, R, phi, e, work);
            } else if (c.leaf()) {
                detail::add_exact<D>(kernel_, s_, x, c.begin, c.end, phi, e);
            } else {
                for (int k = 0; k < c.children; ++k) stack.push_back(c.first_child + k);
            }
        }
    }

    K kernel_;
    TreeOptions options_;
    Multipole<D> expansion_;
    Tree<D> tree_;
    detail::SourceArrays<D> s_;
    std::vector<double> m_;
};

// One call: build the tree for the sources and evaluate at the targets.
template <int D, RadialKernel K>
Field<D> treecode(const K& kernel, const Sources<D>& sources, const Points<D>& targets, const TreeOptions& options) {
    return Treecode<D, K>(kernel, sources, options).evaluate(targets);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
