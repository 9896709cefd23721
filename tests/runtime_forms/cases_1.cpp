// Part 1 of the tables runtime_forms_test compares (static_case.hpp).
#include "static_case.hpp"

#include <mollify/tables/combo/m_3_base_wendland_k_1_l_1_D1.hpp>
#include <mollify/tables/mollifier/M_1_D2.hpp>
#include <mollify/tables/mollifier/M_2_order_4_D1.hpp>
#include <mollify/tables/wendland/k_0_D2.hpp>
#include <mollify/tables/wendland_missing/k_1_D1.hpp>

namespace mollify::testing {

std::vector<Case> cases_1() {
    namespace tables = mollify::tables;
    return {
        case_of<tables::combo_m_3_base_wendland_k_1_l_1_D1>(),
        case_of<tables::mollifier_M_1_D2>(),
        case_of<tables::wendland_k_0_D2>(),
        case_of<tables::mollifier_M_2_order_4_D1>(),
        case_of<tables::wendland_missing_k_1_D1>(),
    };
}

}  // namespace mollify::testing
