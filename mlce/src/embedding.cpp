#include "mlce/embedding.hpp"

#include <stdexcept>
#include <string>

namespace mlce {

DelayEmbedding::DelayEmbedding(std::vector<std::span<const double>> channels, std::size_t dim, std::size_t delay,
                               std::size_t points)
    : channels_(std::move(channels)), dim_(dim), delay_(delay), points_(points) {
  if (channels_.empty()) throw std::invalid_argument("DelayEmbedding: no channel");
  if (dim_ == 0 || delay_ == 0) throw std::invalid_argument("DelayEmbedding: dim and delay must be >= 1");
  for (const auto& c : channels_)
    if (points_ > max_points(c.size(), dim_, delay_))
      throw std::invalid_argument("DelayEmbedding: " + std::to_string(points_) + " points exceed N - (m-1)J = " +
                                  std::to_string(max_points(c.size(), dim_, delay_)));
}

}  // namespace mlce
