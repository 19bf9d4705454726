#include "gridshell/fem/limit_type.h"

#include "gridshell/core/enum_words.h"

namespace gridshell::fem {

namespace {

constexpr EnumWords<LimitType, 3> kLimitTypeWords{{{"limit point", LimitType::limit_point},
                                                   {"bifurcation", LimitType::bifurcation},
                                                   {"none", LimitType::none}}};

}  // namespace

const char* to_string(LimitType type) {
  return word_of(type, kLimitTypeWords);
}

LimitType parse_limit_type(const std::string& word) {
  return parse_word(word, "limit_type", kLimitTypeWords);
}

}  // namespace gridshell::fem
