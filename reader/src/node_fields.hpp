#pragma once
// Where a node field of a channel spec lives: a group of the .mov row (format doc section 3) and
// a component in it. Shared by the text and NetCDF readers.
#include <cstddef>
#include <optional>
#include <string_view>

#include "mlce/reader/orientation.hpp"

namespace mlce::reader::detail {

enum class NodeGroup { position, orientation, velocity, angular_velocity, acceleration, angular_acceleration };

struct NodeField {
  NodeGroup group;
  std::size_t component;  ///< 0-based within the group
};

std::optional<NodeField> parse_node_field(std::string_view field);

/// 1-based column of the field in a .mov row of a node with orientation `o`.
inline std::size_t mov_column(NodeField f, Orientation o) {
  const std::size_t nor = orientation_size(o);
  switch (f.group) {
    case NodeGroup::position: return 2 + f.component;
    case NodeGroup::orientation: return 5 + f.component;
    case NodeGroup::velocity: return 5 + nor + f.component;
    case NodeGroup::angular_velocity: return 8 + nor + f.component;
    case NodeGroup::acceleration: return 11 + nor + f.component;
    default: return 14 + nor + f.component;
  }
}

}  // namespace mlce::reader::detail
