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

// _scan_contacts: per robot-terrain contact that is not excluded, (its index in d->contact, the
// robot geom, +1 when the robot geom is the contact's second geom else -1) into out (3 per
// contact, d->ncon rows at most); returns their number.
inline std::int64_t terrain_contacts(const mjData* d, const std::int8_t* roles, std::int64_t ngeom,
                                     std::int64_t* out) {
  std::int64_t count = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.exclude != 0) continue;
    const int g1 = c.geom[0], g2 = c.geom[1];
    const std::int8_t first = g1 >= 0 && g1 < ngeom ? roles[g1] : OTHER;
    const std::int8_t second = g2 >= 0 && g2 < ngeom ? roles[g2] : OTHER;
    if (first == TERRAIN && second == ROBOT) {
      out[3 * count] = i, out[3 * count + 1] = g2, out[3 * count + 2] = 1;
      ++count;
    } else if (first == ROBOT && second == TERRAIN) {
      out[3 * count] = i, out[3 * count + 1] = g1, out[3 * count + 2] = -1;
      ++count;
    }
  }
  return count;
}

// Whether a robot geom outside `allowed` (one flag per geom) touches the terrain in a contact
// that is not excluded.
inline bool touches_outside(const mjData* d, const std::int8_t* roles, const std::int8_t* allowed,
                            std::int64_t ngeom) {
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.exclude != 0) continue;
    const int g1 = c.geom[0], g2 = c.geom[1];
    const std::int8_t first = g1 >= 0 && g1 < ngeom ? roles[g1] : OTHER;
    const std::int8_t second = g2 >= 0 && g2 < ngeom ? roles[g2] : OTHER;
    if (first == TERRAIN && second == ROBOT && !allowed[g2]) return true;
    if (first == ROBOT && second == TERRAIN && !allowed[g1]) return true;
  }
  return false;
}

}  // namespace va::mj
