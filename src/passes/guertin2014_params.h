// Parameters of reconstruct_guertin2014 (Guertin, McGuire, Nowrouzezahrai, HPG 2014;
// docs/guertin2014.md): those of docs/spec.md §3 and the filters' options (McGuire2012Params), and
// the paper's two constants of the sampling and weighting.
//
// | name  | default (the paper's) | allowed          |
// |-------|-----------------------|------------------|
// | gamma | 1.5                   | finite, > 0 (px) |
// | kappa | 40                    | finite, > 0      |
#pragma once

#include "passes/mcguire2012_params.h"

namespace blurlab {

struct Guertin2014Params : McGuire2012Params {
  float gamma = 1.5f;
  float kappa = 40.0f;

  // Throws std::invalid_argument naming the parameter, its value and the allowed range.
  void validate() const {
    McGuire2012Params::validate();
    if (!std::isfinite(gamma) || !(gamma > 0.0f))
      throw std::invalid_argument("blurlab: gamma = " + std::to_string(gamma) +
                                  " must be finite and > 0 (pixels)");
    if (!std::isfinite(kappa) || !(kappa > 0.0f))
      throw std::invalid_argument("blurlab: kappa = " + std::to_string(kappa) +
                                  " must be finite and > 0");
  }
};

}  // namespace blurlab
