// rfidray.tag_coupling: the tag antenna model (core/tag_antenna.h) for one tag, antenna, chip and backing at one
// frequency — the same text forms and the same numbers as `rfidray link --tag-antenna … --json`'s tag_antenna.
#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include "core/error.h"
#include "core/tag_antenna.h"
#include "core/units.h"
#include "io/tag_antenna_spec.h"
#include "python/bindings/bindings.h"

namespace rfidray::py {

void bind_tag(pyb::module_& m) {
  m.def(
      "tag_coupling",
      [](const std::string& antenna, const std::string& chip, const std::string& backing, double frequency_hz) {
        const TagAntennaSpec a = io::parse_tag_antenna(antenna, "antenna");
        const TagChipSpec c = io::parse_tag_chip(chip, "chip");
        const TagBackingSpec b = io::parse_tag_backing(backing, "backing");
        if (b.kind == TagBackingSpec::Kind::kScene)
          throw InputError("backing: 'scene' needs a scene; give none or MATERIAL:DISTANCE_M here");
        validate(a, c, b, "tag");
        if (!(frequency_hz > 0.0 && frequency_hz <= 1e11)) throw InputError("frequency_hz: must be in (0, 1e11] Hz");
        const TagCoupling t = tag_coupling(a, c, b.kind == TagBackingSpec::Kind::kGiven ? &b.material : nullptr, b.distance_m, frequency_hz);
        pyb::dict d;
        d["impedance_ohm"] = t.antenna_impedance_ohm;
        d["free_space_impedance_ohm"] = t.free_space_impedance_ohm;
        d["chip_impedance_ohm"] = t.chip_impedance_ohm;
        d["power_transfer"] = t.power_transfer;
        d["power_transfer_db"] = linear_to_db(t.power_transfer);
        d["chip_power_factor_db"] = linear_to_db(t.chip_power_factor);
        d["modulation_factor"] = t.modulation_factor;
        d["backscatter_phase_rad"] = t.backscatter_phase_rad;
        d["image_factor_normal"] = backing_image_factor(b, 1.0, frequency_hz);
        return d;
      },
      pyb::arg("antenna"), pyb::arg("chip") = "matched", pyb::arg("backing") = "none",
      pyb::arg("frequency_hz") = 866e6,
      "The tag antenna model at one frequency: antenna 'dipole:L:A[:SIGMA]' or 'table:FILE.csv', chip "
      "'matched[:HZ]' | 'series:R:C' | 'parallel:R:C', backing 'none' | 'MATERIAL:DISTANCE_M' (metal, water, wood, …) | 'dielectric:EPS:SIGMA:DISTANCE_M'. Returns the "
      "impedances (complex, ohm), the power transfer tau, F (dB), K, the backscatter turn and the image factor "
      "at normal incidence (docs/tag-antenna.md).");
}

}  // namespace rfidray::py
