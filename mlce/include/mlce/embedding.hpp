#pragma once
// Delay embedding as a view (paper 001 eqs. 15-17): point i of an m-dimensional embedding with
// delay J is (x[i], x[i+J], ..., x[i+(m-1)J]) for each channel, never materialised as an M x m
// matrix. It is also the nanoflann dataset adaptor, so the kd-tree runs over the samples directly.
#include <cstddef>
#include <span>
#include <vector>

namespace mlce {

class DelayEmbedding {
 public:
  /// `points` = how many embedded points the view exposes (<= max_points()).
  DelayEmbedding(std::vector<std::span<const double>> channels, std::size_t dim, std::size_t delay,
                 std::size_t points);

  /// M = N - (m-1)J (eq. 17).
  static std::size_t max_points(std::size_t n, std::size_t dim, std::size_t delay) {
    const std::size_t span = (dim - 1) * delay;
    return n > span ? n - span : 0;
  }

  std::size_t dimension() const { return dim_ * channels_.size(); }
  std::size_t embedding_dim() const { return dim_; }
  std::size_t delay() const { return delay_; }
  std::size_t size() const { return points_; }

  /// Coordinate d of point i: channel d / m, lag (d % m) * J.
  double coordinate(std::size_t i, std::size_t d) const {
    return channels_[d / dim_][i + (d % dim_) * delay_];
  }
  void point(std::size_t i, double* out) const {
    for (std::size_t d = 0, D = dimension(); d < D; ++d) out[d] = coordinate(i, d);
  }
  double squared_distance(std::size_t i, std::size_t j) const {
    double s = 0.0;
    for (std::size_t d = 0, D = dimension(); d < D; ++d) {
      const double e = coordinate(i, d) - coordinate(j, d);
      s += e * e;
    }
    return s;
  }

  /// Squared distance from point i to the point a fraction f in [0, 1] of the way from point j to
  /// point j + 1 (linear interpolation along the sampled trajectory; j + 1 must exist).
  double squared_distance_between(std::size_t i, std::size_t j, double f) const {
    double s = 0.0;
    for (std::size_t d = 0, D = dimension(); d < D; ++d) {
      const double e = coordinate(i, d) - ((1.0 - f) * coordinate(j, d) + f * coordinate(j + 1, d));
      s += e * e;
    }
    return s;
  }

  // nanoflann dataset-adaptor interface
  std::size_t kdtree_get_point_count() const { return points_; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return coordinate(i, d); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const { return false; }

 private:
  std::vector<std::span<const double>> channels_;
  std::size_t dim_;
  std::size_t delay_;
  std::size_t points_;
};

}  // namespace mlce
