#pragma once
// The first word of every reading (reading.hpp: the divergence curve's; modes.hpp: the record's damped
// modes'), in a header of its own so that the estimator's options can hold the modes' options
// (MlceOptions::record_modes) without the reading's header, which reads the estimator's result.
namespace mlce {

enum class Stability { stable, neutral, unstable, undetermined };

const char* to_string(Stability s);

}  // namespace mlce
