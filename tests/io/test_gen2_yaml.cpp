// The `gen2:` block of a scenario's antenna: presets, keys, ports resolved by name, and errors naming
// file:line and field.
#include <gtest/gtest.h>

#include "core/error.h"
#include "io/scenario_yaml.h"

namespace rfidray::io {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, "s.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kHead = R"(duration_s: 1
tags: [{name: t, position: [1, 0, 1]}]
antennas:
  - name: left
    position: [0, 0, 1]
)";

TEST(Gen2Yaml, PresetAndKeys) {
  const Scenario s = parse_scenario(std::string(kHead) + R"(    gen2:
      preset: dense_reader_m4
      session: 2
      target: A
      q: 6
      q_algorithm: fixed
      select_prefix: pal
      capture_db: 6
      ports: [{antenna: left, dwell_ms: 200}, {antenna: right, dwell_ms: 300}]
  - name: right
    position: [2, 0, 1]
)", "s.yaml");
  ASSERT_TRUE(s.antennas[0].gen2);
  const Gen2ReaderSpec& g = *s.antennas[0].gen2;
  EXPECT_EQ(g.preset, "dense_reader_m4");
  EXPECT_DOUBLE_EQ(g.link.tari_s, 25e-6);
  EXPECT_DOUBLE_EQ(g.link.blf_hz, 250e3);
  EXPECT_EQ(g.link.encoding, Gen2Encoding::kMiller4);
  EXPECT_EQ(g.session, 2);
  EXPECT_EQ(g.target, Gen2Target::kA);
  EXPECT_EQ(g.q, 6);
  EXPECT_EQ(g.q_mode, Gen2QMode::kFixed);
  EXPECT_EQ(g.select_prefix, "pal");
  ASSERT_TRUE(g.capture_ratio_db);
  EXPECT_DOUBLE_EQ(*g.capture_ratio_db, 6.0);
  ASSERT_EQ(g.ports.size(), 2u);
  EXPECT_EQ(g.ports[1].antenna, 1u);
  EXPECT_DOUBLE_EQ(g.ports[1].dwell_s, 0.3);
  EXPECT_FALSE(s.antennas[1].gen2);
}

TEST(Gen2Yaml, ExplicitLinkOverridesThePreset) {
  const Scenario s = parse_scenario(std::string(kHead) + R"(    gen2: {preset: max_throughput, tari_us: 12.5, blf_khz: 320, encoding: miller2, trext: true}
)", "s.yaml");
  const Gen2LinkParams& l = s.antennas[0].gen2->link;
  EXPECT_DOUBLE_EQ(l.tari_s, 12.5e-6);
  EXPECT_DOUBLE_EQ(l.blf_hz, 320e3);
  EXPECT_EQ(l.encoding, Gen2Encoding::kMiller2);
  EXPECT_TRUE(l.trext);
}

TEST(Gen2Yaml, ErrorsNameFileLineAndField) {
  auto gen2 = [](const std::string& body) { return std::string(kHead) + "    gen2:\n" + body; };
  EXPECT_NE(error_of(gen2("      tari_us: 3\n")).find("s.yaml:7: field 'antennas[0].gen2.tari_us'"), std::string::npos)
      << error_of(gen2("      tari_us: 3\n"));
  EXPECT_NE(error_of(gen2("      session: 4\n")).find("s.yaml:7: field 'antennas[0].gen2.session'"), std::string::npos);
  EXPECT_NE(error_of(gen2("      target: C\n")).find("field 'antennas[0].gen2.target'"), std::string::npos);
  EXPECT_NE(error_of(gen2("      encoding: miller3\n")).find("s.yaml:7: field 'antennas[0].gen2.encoding'"), std::string::npos);
  EXPECT_NE(error_of(gen2("      preset: fastest\n")).find("unknown preset 'fastest' (max_throughput, dense_reader_m4)"),
            std::string::npos);
  EXPECT_NE(error_of(gen2("      q: 16\n")).find("field 'antennas[0].gen2.q'"), std::string::npos);
  EXPECT_NE(error_of(gen2("      q_algorithm: smart\n")).find("gen2.q_algorithm"), std::string::npos);
  EXPECT_NE(error_of(gen2("      sesion: 2\n")).find("did you mean 'session'"), std::string::npos);
  EXPECT_NE(error_of(gen2("      blf_khz: 40\n      tari_us: 6.25\n")).find("s.yaml:7: field 'antennas[0].gen2.blf_khz'"),
            std::string::npos)
      << error_of(gen2("      blf_khz: 40\n      tari_us: 6.25\n"));
  EXPECT_NE(error_of(gen2("      ports: [{antenna: nowhere, dwell_ms: 10}, {antenna: left, dwell_ms: 10}]\n"))
                .find("s.yaml:7: field 'antennas[0].gen2.ports[0].antenna': no antenna named 'nowhere'"),
            std::string::npos);
  EXPECT_NE(error_of(gen2("      ports: [{antenna: left}, {antenna: left, dwell_ms: 10}]\n")).find("dwell_ms"),
            std::string::npos);
  EXPECT_NE(error_of(gen2("      s23_persistence_s: 1\n")).find("s.yaml:7: field 'antennas[0].gen2.s23_persistence_s'"),
            std::string::npos);
}

}  // namespace
}  // namespace rfidray::io
