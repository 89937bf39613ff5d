// MuJoCo's contact list read in place: the simulation's per-tick contact scans in C++, a
// line-by-line port of virtual_actuators.simulation.contact_queries.ContactQueries._scan_contacts
// (the robot-terrain contacts) and of the runner's fall test on the touching geoms
// (gaits.runner.has_fallen's "a part other than a foot touches the ground").
//
// Built only when MuJoCo's headers were found at build time (CMakeLists.txt: VA_MUJOCO); the
// layout of mjData and mjContact is that of the headers' version, so the Python side uses these
// scans only when the running MuJoCo is that version (mj_version() == mjVERSION_HEADER).
#pragma once

#include <mujoco/mjdata.h>

#include <cstdint>

namespace va::mj {

// A geom's role in a contact: neither the terrain's nor the robot's, the terrain's, the robot's.
constexpr std::int8_t OTHER = 0, TERRAIN = 1, ROBOT = 2;

// The robot geom of a robot-terrain contact that is not excluded (-1 for any other contact), and
// sign: +1 when it is the contact's second geom (MuJoCo's force acts on that one), else -1.
inline int robot_geom(const mjContact& c, const std::int8_t* roles, std::int64_t ngeom, int* sign) {
  if (c.exclude != 0) return -1;
  const int g1 = c.geom[0], g2 = c.geom[1];
  const std::int8_t first = g1 >= 0 && g1 < ngeom ? roles[g1] : OTHER;
  const std::int8_t second = g2 >= 0 && g2 < ngeom ? roles[g2] : OTHER;
  if (first == TERRAIN && second == ROBOT) return *sign = 1, g2;
  if (first == ROBOT && second == TERRAIN) return *sign = -1, g1;
  return -1;
}

// _scan_contacts: per robot-terrain contact that is not excluded, (its index in d->contact, the
// robot geom, its sign) into out (3 per contact, d->ncon rows at most); returns their number.
inline std::int64_t terrain_contacts(const mjData* d, const std::int8_t* roles, std::int64_t ngeom,
                                     std::int64_t* out) {
  std::int64_t count = 0;
  int sign = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const int geom = robot_geom(d->contact[i], roles, ngeom, &sign);
    if (geom < 0) continue;
    out[3 * count] = i, out[3 * count + 1] = geom, out[3 * count + 2] = sign;
    ++count;
  }
  return count;
}

// Whether a robot geom outside `allowed` (one flag per geom) touches the terrain in a contact
// that is not excluded.
inline bool touches_outside(const mjData* d, const std::int8_t* roles, const std::int8_t* allowed,
                            std::int64_t ngeom) {
  int sign = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const int geom = robot_geom(d->contact[i], roles, ngeom, &sign);
    if (geom >= 0 && !allowed[geom]) return true;
  }
  return false;
}

// The OR of bits[geom] over the robot geoms touching the terrain in contacts not excluded: the
// contact switches of up to 63 frames in one pass (bit k set: a geom of frame k touches).
inline std::int64_t touch_mask(const mjData* d, const std::int8_t* roles, const std::int64_t* bits,
                               std::int64_t ngeom) {
  std::int64_t mask = 0;
  int sign = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const int geom = robot_geom(d->contact[i], roles, ngeom, &sign);
    if (geom >= 0) mask |= bits[geom];
  }
  return mask;
}

}  // namespace va::mj
