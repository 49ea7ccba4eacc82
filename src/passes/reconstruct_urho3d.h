// reconstruct_urho3d, the Urho3D thesis's reconstruct pass as printed there (docs/spec.md §3
// variant): a fragment pass, the seed's baseline — shaders/passes/reconstruct_urho3d.glsl,
// NumPy twin blurlab.reference.urho3d, tests/test_reconstruct_urho3d.py.
#pragma once

#include "passes/mcguire2012_params.h"
#include "passes/post_process.h"

namespace blurlab {

class ReconstructUrho3dPass : public PostProcessPass {
 public:
  explicit ReconstructUrho3dPass(std::shared_ptr<Context> context);
  // As ReconstructMcGuire2012Pass, plus the 64 x 64 R32F jitter texture and `far`, the depth
  // that +inf is read as (> 0).
  void run(const Texture& color, const Texture& depth, const Texture& motion,
           const Texture& neighbor_max, const Texture& jitter, const Texture& result,
           const McGuire2012Params& params, float far);
};

}  // namespace blurlab
