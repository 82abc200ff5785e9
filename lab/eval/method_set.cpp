#include "lab/eval/method_set.hpp"

namespace probeless::eval {

const std::vector<std::string>& all_method_names() {
  return occlusion::method_names();
}

}  // namespace probeless::eval
