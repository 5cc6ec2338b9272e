#pragma once
// Comma-separated numbers given to a command-line option ("--antenna 1.5,-2,0", "--box x0,y0,z0,x1,y1,z1").
// Pure functions; safe from any thread.
#include <string>
#include <vector>

namespace rfidray::cli {

// Parses "a,b,c". Throws InputError "option OPTION: 'ITEM' is not a number (in 'TEXT')" for an item that is not
// a whole finite number; with `coordinates`, "... is not a coordinate ..." also for one beyond core/limits.h's
// coordinate range (|x| ≤ 1e8 m).
std::vector<double> parse_number_list(const std::string& text, const std::string& option, bool coordinates = false);

}  // namespace rfidray::cli
