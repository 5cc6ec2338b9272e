// The antenna file (io/antenna_file.h): round trip, and every malformed file named by file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "io/antenna_file.h"
#include "tests/support/input_error.h"

namespace rfidray::io {
namespace {

loc::AntennaCalibration example() {
  loc::AntennaCalibration c;
  c.antenna = "a0";
  c.phase_centre_offset_m = Vec3(0.031, -0.0125, 0.002);
  c.phase_centre_offset_sd_m = Vec3(0.004, 0.003, 0.05);
  c.frequencies_hz = {920.625e6, 921.125e6, 921.625e6};
  c.carrier_offsets_rad = {0.0, 1.25, -2.5};
  c.carrier_offsets_sd_rad = {0.0, 0.01, 0.02};
  c.pattern_rad = {0.2, 0.0, 0.61, -0.1, 0.05};
  c.pattern_sd_rad = {0.01, 1.0, 0.03, 0.5, 0.9};
  c.residual_rms_rad = 0.083;
  c.reads_used = 12345;
  c.tags_used = 18;
  return c;
}

TEST(AntennaFile, RoundTrip) {
  std::ostringstream out;
  write_antenna_file(out, example());
  const loc::AntennaCalibration c = parse_antenna_yaml(out.str(), "a.yaml");
  const loc::AntennaCalibration e = example();
  EXPECT_EQ(c.antenna, e.antenna);
  EXPECT_TRUE(c.phase_centre_offset_m.isApprox(e.phase_centre_offset_m, 1e-9));
  EXPECT_TRUE(c.phase_centre_offset_sd_m.isApprox(e.phase_centre_offset_sd_m, 1e-9));
  EXPECT_EQ(c.frequencies_hz, e.frequencies_hz);
  EXPECT_EQ(c.carrier_offsets_rad, e.carrier_offsets_rad);
  EXPECT_EQ(c.carrier_offsets_sd_rad, e.carrier_offsets_sd_rad);
  EXPECT_EQ(c.pattern_rad, e.pattern_rad);
  EXPECT_EQ(c.pattern_sd_rad, e.pattern_sd_rad);
  EXPECT_DOUBLE_EQ(c.residual_rms_rad, e.residual_rms_rad);
  EXPECT_EQ(c.reads_used, e.reads_used);
  EXPECT_EQ(c.tags_used, e.tags_used);
  // Writing is deterministic.
  std::ostringstream again;
  write_antenna_file(again, c);
  EXPECT_EQ(again.str(), out.str());
}

TEST(AntennaFile, GeometryCovarianceRoundTripsAndIsChecked) {
  loc::AntennaCalibration e = example();
  // A covariance with correlations (offset x against the az² curvature, as a calibration finds).
  Eigen::Matrix<double, loc::kGeometryTerms, loc::kGeometryTerms> a;
  for (int i = 0; i < loc::kGeometryTerms; ++i)
    for (int j = 0; j < loc::kGeometryTerms; ++j) a(i, j) = 0.01 * std::sin(1.0 + i * 3.0 + j * 7.0);
  e.geometry_covariance = a * a.transpose();
  std::ostringstream out;
  write_antenna_file(out, e);
  const std::string text = out.str();
  const loc::AntennaCalibration c = parse_antenna_yaml(text, "a.yaml");
  EXPECT_TRUE(c.geometry_covariance.isApprox(e.geometry_covariance, 1e-9));
  EXPECT_TRUE(c.geometry_covariance_or_sd().isApprox(e.geometry_covariance, 1e-9));
  // Without it, the sd's are taken as uncorrelated.
  const loc::AntennaCalibration plain = example();
  EXPECT_DOUBLE_EQ(plain.geometry_covariance_or_sd()(0, 0), 0.004 * 0.004);
  EXPECT_DOUBLE_EQ(plain.geometry_covariance_or_sd()(5, 5), 0.03 * 0.03);
  EXPECT_EQ(plain.geometry_covariance_or_sd()(0, 5), 0.0);
  std::ostringstream plain_out;
  write_antenna_file(plain_out, plain);
  EXPECT_EQ(plain_out.str().find("geometry_covariance"), std::string::npos);
  // Malformed: the error names the file, the line and the field.
  const size_t at = text.find("geometry_covariance:");
  ASSERT_NE(at, std::string::npos);
  const size_t row = text.find("  - [", at);
  const size_t row_end = text.find('\n', row);
  auto with_row = [&](const std::string& replacement) {
    return text.substr(0, row) + replacement + text.substr(row_end);
  };
  auto error = [](const std::string& t) { return testing::input_error_of([&] { parse_antenna_yaml(t, "ant.yaml"); }); };
  const std::string short_row = error(with_row("  - [1, 2, 3]"));
  EXPECT_NE(short_row.find("ant.yaml:"), std::string::npos) << short_row;
  EXPECT_NE(short_row.find("geometry_covariance[0]"), std::string::npos) << short_row;
  EXPECT_NE(short_row.find("needs 8 numbers"), std::string::npos) << short_row;
  // Row 0 changed: no longer symmetric.
  std::string asym = "  - [";
  for (int j = 0; j < loc::kGeometryTerms; ++j) asym += (j ? ", " : "") + std::to_string(j == 3 ? 0.5 : e.geometry_covariance(0, j));
  EXPECT_NE(error(with_row(asym + "]")).find("must be symmetric"), std::string::npos) << error(with_row(asym + "]"));
  // Symmetric but indefinite: a negative variance.
  loc::AntennaCalibration neg = e;
  neg.geometry_covariance(2, 2) = -1.0;
  std::ostringstream neg_out;
  write_antenna_file(neg_out, neg);
  const std::string indefinite = error(neg_out.str());
  EXPECT_NE(indefinite.find("positive semi-definite"), std::string::npos) << indefinite;
  EXPECT_NE(error(with_row("  - [1, 2, nan, 4, 5, 6, 7, 8]")).find("geometry_covariance[0][2]"), std::string::npos);
  std::string seven_rows = text;
  seven_rows.erase(row, row_end - row + 1);
  EXPECT_NE(error(seven_rows).find("must be 8 rows"), std::string::npos) << error(seven_rows);
}

std::string error_of(const std::string& text) {
  return testing::input_error_of([&] { parse_antenna_yaml(text, "ant.yaml"); });
}

std::string replace_line(const std::string& text, const std::string& key, const std::string& line) {
  std::istringstream in(text);
  std::string out, l;
  while (std::getline(in, l)) out += (l.rfind(key + ":", 0) == 0 ? line : l) + "\n";
  return out;
}

// What calibrate could not determine travels with the file, and is checked when read.
TEST(AntennaFile, NotFittedTermsRoundTripAndAreChecked) {
  loc::AntennaCalibration e = example();
  e.not_fitted = {{"dz", "reference tags and antenna positions lie in one plane: \"second order\""}, {"el", "el = 0"}};
  e.prior_bounded = {{"az2", "sd 0.9 of the prior's"}};
  e.allowance_base_rad = 0.12;
  e.allowance_smooth_factor = 2.5;
  e.allowance_samples = 250;
  e.allowance_coverage = 0.952;
  std::ostringstream out;
  write_antenna_file(out, e);
  const loc::AntennaCalibration c = parse_antenna_yaml(out.str(), "a.yaml");
  ASSERT_TRUE(c.has_allowance());
  EXPECT_DOUBLE_EQ(c.allowance_base_rad, 0.12);
  EXPECT_DOUBLE_EQ(c.allowance_smooth_factor, 2.5);
  EXPECT_EQ(c.allowance_samples, 250);
  EXPECT_DOUBLE_EQ(c.allowance_coverage, 0.952);
  EXPECT_FALSE(parse_antenna_yaml([] {
    std::ostringstream o;
    write_antenna_file(o, example());
    return o.str();
  }(), "b.yaml").has_allowance());
  ASSERT_EQ(c.not_fitted.size(), 2u);
  EXPECT_EQ(c.not_fitted[0].term, "dz");
  EXPECT_EQ(c.not_fitted[0].why, e.not_fitted[0].why);
  EXPECT_EQ(c.not_fitted[1].term, "el");
  ASSERT_EQ(c.prior_bounded.size(), 1u);
  EXPECT_EQ(c.prior_bounded[0].term, "az2");
  std::ostringstream again;
  write_antenna_file(again, c);
  EXPECT_EQ(again.str(), out.str());
  std::string negative = out.str();
  negative.replace(negative.find("base_rad: 0.12"), 14, "base_rad: -0.1");
  EXPECT_NE(error_of(negative).find("allowance.base_rad"), std::string::npos) << error_of(negative);
  std::string bad = out.str();
  bad.replace(bad.find("{term: el,"), 10, "{term: ez,");
  const std::string msg = error_of(bad);
  EXPECT_NE(msg.find("not_fitted[1].term"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must be one of"), std::string::npos) << msg;
}

// The allowance per band of tag spacing travels with the file (the last band open above), and bands that
// overlap, run backwards or have a negative value are refused with their item named.
TEST(AntennaFile, AllowanceBandsRoundTripAndAreChecked) {
  loc::AntennaCalibration e = example();
  e.allowance_base_rad = 0.24;
  e.allowance_smooth_factor = 0.0;
  e.allowance_samples = 460;
  e.allowance_coverage = 0.95;
  e.allowance_bands = {{0.0, 0.1628, 0.34, 0.5, 211, 0.953}, {0.1628, std::numeric_limits<double>::infinity(), 0.09, 0.0, 249, 0.952}};
  std::ostringstream out;
  write_antenna_file(out, e);
  const loc::AntennaCalibration c = parse_antenna_yaml(out.str(), "a.yaml");
  ASSERT_EQ(c.allowance_bands.size(), 2u);
  EXPECT_DOUBLE_EQ(c.allowance_bands[0].spacing_below_m, 0.1628);
  EXPECT_DOUBLE_EQ(c.allowance_bands[0].base_rad, 0.34);
  EXPECT_DOUBLE_EQ(c.allowance_bands[0].smooth_factor, 0.5);
  EXPECT_EQ(c.allowance_bands[0].samples, 211);
  EXPECT_TRUE(std::isinf(c.allowance_bands[1].spacing_below_m));
  EXPECT_EQ(c.allowance_band_for(0.08), &c.allowance_bands[0]);
  EXPECT_EQ(c.allowance_band_for(0.1628), &c.allowance_bands[1]);  // from inclusive, below exclusive
  EXPECT_EQ(c.allowance_band_for(std::numeric_limits<double>::quiet_NaN()), nullptr);
  std::ostringstream again;
  write_antenna_file(again, c);
  EXPECT_EQ(again.str(), out.str());
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = out.str();
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return error_of(t.replace(at, from.size(), to));
  };
  const std::string overlap = with("{spacing_from_m: 0.1628, base_rad", "{spacing_from_m: 0.1, base_rad");
  EXPECT_NE(overlap.find("allowance.bands[1].spacing_from_m"), std::string::npos) << overlap;
  EXPECT_NE(overlap.find("ascending and disjoint"), std::string::npos) << overlap;
  const std::string empty = with("spacing_below_m: 0.1628", "spacing_below_m: 0");
  EXPECT_NE(empty.find("allowance.bands[0].spacing_below_m"), std::string::npos) << empty;
  const std::string negative = with("base_rad: 0.34", "base_rad: -0.34");
  EXPECT_NE(negative.find("allowance.bands[0].base_rad"), std::string::npos) << negative;
  const std::string unknown = with("samples: 211", "tags: 211");
  EXPECT_NE(unknown.find("unknown key 'tags'"), std::string::npos) << unknown;
}

// A file of a calibration that kept nothing (calibrate's held-out check): no carriers, the why, no residual, and
// the allowance; it round-trips, and the why is refused beside carriers.
TEST(AntennaFile, NothingCalibratedRoundTrips) {
  loc::AntennaCalibration e;
  e.antenna = "a0";
  e.carriers_not_fitted = "cross-validated over 6 runs in 2 folds: \"nothing\" localizes held-out tags best";
  e.residual_rms_rad = std::numeric_limits<double>::quiet_NaN();
  e.allowance_base_rad = 0.2;
  e.allowance_smooth_factor = 0.0;
  e.allowance_samples = 18;
  std::ostringstream out;
  write_antenna_file(out, e);
  EXPECT_NE(out.str().find("frequencies_hz: []"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("residual_rms_rad"), std::string::npos) << out.str();
  const loc::AntennaCalibration c = parse_antenna_yaml(out.str(), "a.yaml");
  EXPECT_TRUE(c.frequencies_hz.empty());
  EXPECT_FALSE(c.has_carrier_offsets());
  EXPECT_EQ(c.carriers_not_fitted, e.carriers_not_fitted);
  EXPECT_TRUE(std::isnan(c.residual_rms_rad));
  EXPECT_TRUE(c.has_allowance());
  std::ostringstream again;
  write_antenna_file(again, c);
  EXPECT_EQ(again.str(), out.str());
  std::ostringstream with_carriers;
  loc::AntennaCalibration both = example();
  both.carriers_not_fitted = "why";
  write_antenna_file(with_carriers, both);
  const std::string msg = error_of(with_carriers.str());
  EXPECT_NE(msg.find("carrier_offsets_not_fitted"), std::string::npos) << msg;
  EXPECT_NE(msg.find("without carriers"), std::string::npos) << msg;
}

TEST(AntennaFile, MalformedFilesNameFileLineAndField) {
  std::ostringstream good;
  write_antenna_file(good, example());
  const std::string g = good.str();
  auto line_of = [&](const std::string& key) {
    std::istringstream in(g);
    std::string l;
    for (int n = 1; std::getline(in, l); ++n)
      if (l.rfind(key + ":", 0) == 0) return n;
    return -1;
  };
  struct Case {
    std::string key, line, expect;
  };
  const std::vector<Case> cases = {
      {"phase_centre_offset_m", "phase_centre_offset_m: [0.1, .nan, 0]", "must be a finite number"},
      {"phase_centre_offset_m", "phase_centre_offset_m: [0.1, 0.2]", "needs 3 numbers"},
      {"frequencies_hz", "frequencies_hz: [920e6, 919e6, 921e6]", "ascending"},
      {"carrier_offsets_rad", "carrier_offsets_rad: [0, 1]", "one value per frequency"},
      {"carrier_offsets_rad", "carrier_offsets_rad: [0.5, 1, 2]", "must be 0"},
      {"pattern_terms", "pattern_terms: [az, el, az2, el2, az_el]", "must be 'az_el'"},
      {"pattern_rad", "pattern_rad: [1, 2, x, 4, 5]", "must be a number"},
      {"reads_used", "reads_used: -3", "count"},
      {"tags_used", "tagz_used: 3", "unknown key 'tagz_used'"},
  };
  for (const Case& c : cases) {
    const std::string msg = error_of(replace_line(g, c.key, c.line));
    EXPECT_NE(msg.find("ant.yaml:" + std::to_string(line_of(c.key)) + ":"), std::string::npos) << c.line << " -> " << msg;
    const std::string field = c.key == "tags_used" ? "tagz_used" : c.key;
    EXPECT_NE(msg.find("field '" + field), std::string::npos) << c.line << " -> " << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.line << " -> " << msg;
  }
  // A missing required key is named.
  const std::string missing = error_of(replace_line(g, "antenna", "# no antenna"));
  EXPECT_NE(missing.find("field 'antenna': is required"), std::string::npos) << missing;
  EXPECT_THROW(read_antenna_file("/nonexistent/ant.yaml"), InputError);
}

}  // namespace
}  // namespace rfidray::io
