#pragma once
// The bench's oracle path for the tests that run `runBench` end to end on tiny frames.
#include <memory>

#include "compare/bench/bench.h"
#include "cpu_ref/pipeline.h"

namespace mrr {

inline BenchPath oracleBenchPath() {
  return {"cpu", "cpu_ref, for a test", [](const Scene& scene) -> RenderFn {
            auto r = std::make_shared<Renderer>(scene);
            return [r](const Camera& c, const Constants& k, const RenderOptions& ro) { return r->render(c, k, ro); };
          }};
}

}  // namespace mrr
