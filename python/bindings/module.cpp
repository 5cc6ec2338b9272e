// The _rfidray extension module: the library's objects and runs for Python (rfidray/__init__.py wraps it).
// InputError (bad input, the message naming file, line and field) becomes rfidray.InputError, a ValueError.
#include "core/error.h"
#include "python/bindings/bindings.h"

PYBIND11_MODULE(_rfidray, m) {
  m.doc() = "rfidray: ray-traced multipath channel engine for passive UHF RFID (C++ core)";
  pybind11::register_exception<rfidray::InputError>(m, "InputError", PyExc_ValueError);
  rfidray::py::register_world_loader();
  rfidray::py::bind_scene(m);
  rfidray::py::bind_simulate(m);
  rfidray::py::bind_localize(m);
  rfidray::py::bind_calibrate(m);
  rfidray::py::bind_tag(m);
}
