// MuJoCo's contacts read in place (contacts_view.hpp): ContactView, compiled when MuJoCo's
// headers were found at build time (VA_MUJOCO); MJ_VERSION is then their mjVERSION_HEADER (0
// without them: simulation.contact_queries keeps its Python scan).
#include <cstdint>
#include <vector>

#include "bind_common.hpp"

#ifdef VA_MUJOCO
#include <mujoco/mujoco.h>

#include "contacts_view.hpp"
#endif

namespace va::py {
namespace {

#ifdef VA_MUJOCO
// A simulation's mjModel and mjData (their addresses: mujoco.MjModel._address, MjData._address),
// the roles of its geoms and the running library's mj_contactForce (its address, 0: none). The
// caller keeps both alive as long as the view (Simulator holds them).
class ContactView {
 public:
  // mj_contactForce's signature (the function's address comes from the running library).
  using ContactForce = void (*)(const mjModel*, const mjData*, int, mjtNum[6]);

  ContactView(std::uintptr_t model, std::uintptr_t address, std::int64_t version, const I1& roles,
              std::uintptr_t contact_force)
      : model_(reinterpret_cast<const mjModel*>(model)),
        data_(reinterpret_cast<const mjData*>(address)),
        contact_force_(reinterpret_cast<ContactForce>(contact_force)) {
    require(version == mjVERSION_HEADER, "MuJoCo's version must be the headers' (MJ_VERSION)");
    require(model != 0 && address != 0, "the MjModel's and MjData's addresses must not be null");
    roles_.reserve(roles.shape(0));
    for (std::size_t g = 0; g < roles.shape(0); ++g) {
      const std::int64_t role = roles.data()[g];
      require(role >= va::mj::OTHER && role <= va::mj::ROBOT, "roles must be 0, 1 or 2");
      roles_.push_back(static_cast<std::int8_t>(role));
    }
  }

  // (contact index, robot geom, sign) rows into out ((>= ncon, 3)); their number.
  std::int64_t scan(const nb::ndarray<std::int64_t, nb::numpy, nb::ndim<2>, nb::c_contig,
                                      nb::device::cpu>& out) const {
    require(out.shape(1) == 3 && static_cast<std::int64_t>(out.shape(0)) >= data_->ncon,
            "out must be (>= ncon, 3)");
    return va::mj::terrain_contacts(data_, roles_.data(), static_cast<std::int64_t>(roles_.size()),
                                    out.data());
  }

  // Whether a robot geom whose flag in allowed (one per geom) is 0 touches the terrain.
  bool touches_outside(const nb::ndarray<const std::int8_t, nb::numpy, nb::ndim<1>, nb::c_contig,
                                         nb::device::cpu>& allowed) const {
    require(allowed.shape(0) == roles_.size(), "allowed must hold one flag per geom");
    return va::mj::touches_outside(data_, roles_.data(), allowed.data(),
                                   static_cast<std::int64_t>(roles_.size()));
  }

  // The OR of bits[geom] (one int64 per geom) over the robot geoms touching the terrain.
  std::int64_t touch_mask(const I1& bits) const {
    require(bits.shape(0) == roles_.size(), "bits must hold one entry per geom");
    return va::mj::touch_mask(data_, roles_.data(), bits.data(),
                              static_cast<std::int64_t>(roles_.size()));
  }

  // Per robot-terrain contact on a geom of a group (groups: one per geom, -1 none), in contact
  // order: (group, normal force, tangential force 1, 2) [N] in the contact's frame
  // (mj_contactForce) into out ((>= ncon, 4)); their number. -1 without mj_contactForce.
  std::int64_t forces(
      const I1& groups,
      const nb::ndarray<double, nb::numpy, nb::ndim<2>, nb::c_contig, nb::device::cpu>& out) const {
    require(groups.shape(0) == roles_.size(), "groups must hold one entry per geom");
    require(out.shape(1) == 4 && static_cast<std::int64_t>(out.shape(0)) >= data_->ncon,
            "out must be (>= ncon, 4)");
    if (contact_force_ == nullptr) return -1;
    const auto ngeom = static_cast<std::int64_t>(roles_.size());
    std::int64_t count = 0;
    int sign = 0;
    mjtNum force[6];
    for (int i = 0; i < data_->ncon; ++i) {
      const int geom = va::mj::robot_geom(data_->contact[i], roles_.data(), ngeom, &sign);
      if (geom < 0 || groups.data()[geom] < 0) continue;
      contact_force_(model_, data_, i, force);
      double* row = out.data() + 4 * count++;
      row[0] = static_cast<double>(groups.data()[geom]);
      row[1] = force[0], row[2] = force[1], row[3] = force[2];
    }
    return count;
  }

  std::int64_t ncon() const { return data_->ncon; }

 private:
  const mjModel* model_;
  const mjData* data_;
  ContactForce contact_force_;
  std::vector<std::int8_t> roles_;
};
#endif

}  // namespace

void bind_contacts_view(nb::module_& m) {
#ifdef VA_MUJOCO
  m.attr("MJ_VERSION") = static_cast<std::int64_t>(mjVERSION_HEADER);
  nb::class_<ContactView>(m, "ContactView",
                          "MuJoCo's contact list read in place (simulation.contact_queries): "
                          "the robot-terrain contacts, and whether a geom outside a set "
                          "touches the terrain.")
      .def(nb::init<std::uintptr_t, std::uintptr_t, std::int64_t, const I1&, std::uintptr_t>(),
           "model"_a, "address"_a, "version"_a, "roles"_a, "contact_force"_a)
      .def("scan", &ContactView::scan, "out"_a.noconvert(),
           "ContactQueries._scan_contacts: (contact index, robot geom, sign) rows; their number.")
      .def("forces", &ContactView::forces, "groups"_a, "out"_a.noconvert(),
           "(group, normal, tangent 1, tangent 2) rows of the contacts on grouped geoms (-1: "
           "no mj_contactForce).")
      .def("touches_outside", &ContactView::touches_outside, "allowed"_a,
           "Whether a robot geom not allowed (flag 0) touches the terrain.")
      .def("touch_mask", &ContactView::touch_mask, "bits"_a,
           "The OR of bits[geom] over the robot geoms touching the terrain (contact switches).")
      .def_prop_ro("ncon", &ContactView::ncon);
#else
  m.attr("MJ_VERSION") = static_cast<std::int64_t>(0);
#endif
}

}  // namespace va::py
