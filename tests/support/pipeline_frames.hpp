#pragma once
// Every composite a finite pipeline run produces, in order, handed to `visit` on the test's
// thread: the loop the service-level tests share (lossless runs deliver each frame once).
#include <chrono>
#include <functional>

#include "app/pipeline/pipeline.hpp"

namespace probeless::testing {

inline void for_each_output_frame(Pipeline& pipeline,
                                  const std::function<void(const CompositeFrame&)>& visit) {
  using namespace std::chrono_literals;
  LatestFrame<CompositeFrame>::Sequence seen = 0;
  while (!pipeline.finished() || pipeline.output().sequence() > seen) {
    auto item = pipeline.output().wait_newer(seen, 200ms);
    if (!item) continue;
    seen = item->sequence;
    visit(item->value);
  }
}

}  // namespace probeless::testing
