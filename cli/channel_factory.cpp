#include "cli/channel_factory.h"

#include "core/error.h"

namespace rfidray::cli {

std::vector<std::string> channel_names() { return {"ideal"}; }

std::unique_ptr<Channel> make_channel(const std::string& name, const Scenario&, const std::string& field) {
  if (name == "ideal") return std::make_unique<IdealChannel>();
  std::string known;
  for (const std::string& n : channel_names()) known += (known.empty() ? "" : ", ") + n;
  throw field_error(field, "unknown channel '" + name + "' (known: " + known + ")");
}

}  // namespace rfidray::cli
