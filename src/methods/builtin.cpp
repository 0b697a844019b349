#include "methods/builtin.hpp"

namespace fairspline::detail {

std::vector<MethodInfo> builtin_methods() {
  std::vector<MethodInfo> all;
  for (auto&& group : {li_methods(), jaklic_zagar_methods(), yong_cheng_methods(),
                       kozak_krajnc_methods(), min_energy_methods(), elastic_methods()}) {
    for (auto&& m : group) all.push_back(m);
  }
  return all;
}

}  // namespace fairspline::detail
