#pragma once
// The pieces of the _rfidray extension module, one file per concept; module.cpp calls each bind_* once.
// Every InputError the library throws reaches Python as rfidray.InputError, a ValueError with the same message.
#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

namespace rfidray::py {

namespace pyb = pybind11;

// A Python value (None, bool, int, float, str, dict, list, tuple, NumPy array or scalar) as the YAML node the
// library's checked readers take, so arguments are validated exactly as the same keys in a scenario file.
// Throws InputError naming `field` for anything else.
YAML::Node to_yaml(pyb::handle value, const std::string& field);

// A number for the results' dicts: None where the command's JSON has null (not finite: not measured, no end).
inline pyb::object float_or_none(double v) { return std::isfinite(v) ? pyb::object(pyb::float_(v)) : pyb::none(); }

void bind_scene(pyb::module_& m);     // Scene, Endpoint, Path, Channel
void bind_simulate(pyb::module_& m);  // _simulate, _load_readings
void bind_localize(pyb::module_& m);  // _localize
void bind_calibrate(pyb::module_& m);  // _calibrate
void bind_tag(pyb::module_& m);        // tag_coupling

// Registers the world-file importer with io when this build has one (world_loader_gazebo.cpp or
// world_loader_absent.cpp, chosen in CMake).
void register_world_loader();

}  // namespace rfidray::py
