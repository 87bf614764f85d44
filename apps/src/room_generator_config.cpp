// The room generator's settings checked together: apart from the generator (rooms.cpp), so that
// reading a generator file builds without the navigation code the generator uses (fuzz/).
#include "planemap/apps/rooms.h"

namespace planemap {

std::string RoomGeneratorConfig::CrossCheck() const {
  auto range = [](const char* name, double low, double high) -> std::string {
    return low <= high ? "" : std::string(name) + "_min above " + name + "_max";
  };
  for (const std::string& problem :
       {range("room_size", room_size_min, room_size_max), range("box_narrow", box_narrow_min, box_narrow_max),
        range("box_height", box_height_min, box_height_max), range("box_distance", box_distance_min, box_distance_max),
        range("wall_gap", wall_gap_min, wall_gap_max), range("others", others_min, others_max)}) {
    if (!problem.empty()) return problem;
  }
  if (near_wall_share + corner_share > 1.0) return "near_wall_share + corner_share above 1";
  if (2.0 * start_wall_margin >= room_size_min) return "start_wall_margin leaves no room for the start";
  return "";
}

}  // namespace planemap
