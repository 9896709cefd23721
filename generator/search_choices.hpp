// The choices of the generator's searches for how to write a piece, kept:
// for the missing Wendland functions the series at 0 (series.hpp: its seam
// and order), the series at the edge (edge_series.hpp: its seam and order)
// and the Taylor pieces between (centred_series.hpp: per piece the variant,
// the powers of r and S factored out, the truncation order, the radius of
// the circle whose Cauchy bound proves it, and the sampled scale the bound
// is measured against); for polynomial pieces of potentials, where they are
// written as Taylor polynomials about the midpoints of their halves,
// quarters, ... (emit_plan.cpp's recentre: the sub-pieces' ends and forms).
// The searches were most of `mollify-gen emit` (they try radii, orders and
// variants, sample f at 257 points per piece, evaluate polynomials exactly
// at 33 points per candidate); with a choice known, each truncation bound
// is still proven on every run, once, and the emitted terms are checked
// against the closed form as before (emit_checks.hpp).
// The default catalogue's choices are compiled in (search_choices.def,
// written by `mollify-gen emit --search-choices FILE`, which searches
// afresh; cli_test fails when the file is stale). A closed form the file
// does not know, or whose choice no longer proves its bound, is searched.
#pragma once

#include "closed_form.hpp"

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace mollify::gen {

struct ZeroChoice {  // series.hpp's ZeroSeries
    int m = 0, order = 0;
};

struct EdgeChoice {  // edge_series.hpp's EdgeSeries
    Q r1;
    int order = 0;
};

struct CentredChoice {  // one of centred_series.hpp's CentredPiece
    int k = 0, j = 0;  // the piece is r^-k S^j times the Taylor series of r^k S^-j f
    int order = 0;     // its last power of r - c
    int tenth = 0;     // the bound's circle: radius tenth/20 min(c, 1 - c)
    Q scale;           // min max(|f|, |r f'|) over 257 points of the piece
};
using CentredChoices = std::vector<CentredChoice>;  // the pieces from lo

struct RecentreChoice {  // one sub-piece of emit_plan.cpp's recentre, from the previous one's end
    Q hi;
    bool own = true;  // the piece's own terms, else the Taylor polynomial about the sub-piece's midpoint
};
using RecentreChoices = std::vector<RecentreChoice>;

// The identity of a search: a 64-bit FNV-1a hash of its name (and whatever
// else it reads, as text), f's terms and the rationals it is given, exactly.
std::uint64_t search_key(const std::string& search, const ClosedForm& f, std::initializer_list<Q> given);

// The compiled-in choice by its key; nullptr when unknown or while searching
// afresh.
const ZeroChoice* known_choice(std::uint64_t key, const ZeroChoice*);
const EdgeChoice* known_choice(std::uint64_t key, const EdgeChoice*);
const CentredChoices* known_choice(std::uint64_t key, const CentredChoices*);
const RecentreChoices* known_choice(std::uint64_t key, const RecentreChoices*);
template <class Choice>
const Choice* known_choice(std::uint64_t key) {
    return known_choice(key, static_cast<const Choice*>(nullptr));
}

// From now on every search runs (known_choice gives nullptr) and records its
// choice for search_choices_file: `mollify-gen emit --search-choices`.
void search_afresh();
bool searching_afresh();
void record_choice(std::uint64_t key, const ZeroChoice& choice);
void record_choice(std::uint64_t key, const EdgeChoice& choice);
void record_choice(std::uint64_t key, const CentredChoices& choices);
void record_choice(std::uint64_t key, const RecentreChoices& choices);
// The recorded choices as search_choices.def's text, sorted by search and key.
std::string search_choices_file();

}  // namespace mollify::gen
