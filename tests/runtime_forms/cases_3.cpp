// Part 3 of the tables runtime_forms_test compares (static_case.hpp).
#include "static_case.hpp"

#include <mollify/tables/combo/m_2_base_wendland_k_1_D2.hpp>
#include <mollify/tables/mollifier/M_1_D1.hpp>
#include <mollify/tables/wendland/k_0_l_1_D1.hpp>
#include <mollify/tables/wendland/k_4_D1.hpp>
#include <mollify/tables/wendland/k_4_D3.hpp>
#include <mollify/tables/wendland_missing/k_1_D3.hpp>

namespace mollify::testing {

std::vector<Case> cases_3() {
    namespace tables = mollify::tables;
    return {
        case_of<tables::wendland_missing_k_1_D3>(),
        case_of<tables::combo_m_2_base_wendland_k_1_D2>(),
        case_of<tables::mollifier_M_1_D1>(),
        case_of<tables::wendland_k_0_l_1_D1>(),
        // a power of q times a polynomial the generator does not split (table::Term::split)
        case_of<tables::wendland_k_4_D1>(),
        case_of<tables::wendland_k_4_D3>(),
    };
}

}  // namespace mollify::testing
