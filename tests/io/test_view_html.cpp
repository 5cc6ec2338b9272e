// The view page (io/view_html.h): the data it embeds are the paths it was given, "</script" in any text cannot
// end a script early, and a missing three.js is an input error that leaves no file behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/view_html.h"
#include "raytrace/raytraced_channel.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

const std::string kGroundWall = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/ground_wall.obj";

// The README's hand check: antenna (0, 0, 1), tag (3, 0, 1.5) over ground_wall.obj — LoS, ground, wall.
io::ViewInput ground_wall_view(const std::shared_ptr<const Scene>& scene) {
  io::ViewInput in;
  in.title = "ground wall";
  in.level = "single-bounce";
  in.scene = scene.get();
  Endpoint a, t;
  a.pose.position = Vec3(0, 0, 1);
  t.pose.position = Vec3(3, 0, 1.5);
  in.antennas.push_back({"reader", a.pose});
  in.tags.push_back({"tag", t.pose});
  in.links.push_back({0, 0, 865.7e6, a.pose.position, t.pose.position, RaytracedChannel(scene).paths(a, t, 865.7e6)});
  return in;
}

nlohmann::json embedded_data(const std::string& page) {
  const std::string open = "<script id=\"rfidray-data\" type=\"application/json\">";
  const size_t begin = page.find(open);
  EXPECT_NE(begin, std::string::npos);
  const size_t end = page.find("</script>", begin);
  return nlohmann::json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

TEST(ViewHtml, EmbedsEveryPathWithItsLengthMaterialAndPower) {
  const auto scene = load_scene({kGroundWall}, MaterialAssignment{});
  const io::ViewInput in = ground_wall_view(scene);
  ASSERT_EQ(in.links[0].paths.size(), 3u);
  EXPECT_EQ(io::view_path_count(in), 3u);
  const std::string page = io::view_html(in, "/* three */", "/* orbit */");
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  const nlohmann::json j = embedded_data(page);
  ASSERT_EQ(j["paths"].size(), 3u);
  double strongest_db = -1e9;
  for (size_t i = 0; i < 3; ++i) {
    const Path& p = in.links[0].paths[i];
    const auto& jp = j["paths"][i];
    EXPECT_EQ(jp["kind"], to_string(p.kind));
    EXPECT_EQ(jp["length_m"].get<double>(), p.length_m);
    EXPECT_EQ(jp["material"], p.material);
    EXPECT_EQ(jp["points"].size(), p.kind == PathKind::kReflection ? 3u : 2u);
    EXPECT_LE(jp["relative_db"].get<double>(), 0.0);
    strongest_db = std::max(strongest_db, jp["relative_db"].get<double>());
  }
  EXPECT_EQ(strongest_db, 0.0);
  // The LoS path (strongest, unobstructed) is the reference; the reflections are weaker.
  EXPECT_EQ(j["paths"][0]["kind"], "los");
  EXPECT_EQ(j["paths"][0]["relative_db"].get<double>(), 0.0);
  // One merged triangle list per material: ground_wall.obj is 4 concrete triangles.
  ASSERT_EQ(j["materials"].size(), 1u);
  EXPECT_EQ(j["materials"][0]["name"], "concrete");
  EXPECT_EQ(j["materials"][0]["triangles"], 4);
  EXPECT_EQ(j["materials"][0]["positions"].size(), 4u * 9u);
  // Boresight = local +X of the antenna's orientation (identity here).
  EXPECT_EQ(j["antennas"][0]["boresight"], nlohmann::json({1.0, 0.0, 0.0}));
  // The page draws what it embeds and says so on <body>.
  EXPECT_NE(page.find("data-status=\"loading\" data-errors=\"0\""), std::string::npos);
  EXPECT_NE(page.find("/* three */"), std::string::npos);
  EXPECT_NE(page.find("/* orbit */"), std::string::npos);
}

// Without WebGL the page must not stay blank: the script probes for a context before it creates three.js's
// renderer (which would log an error and throw), says why the view is empty, and still lists every path. The
// behaviour in a browser is checked by tests/python/view_in_chromium.py (Chromium with WebGL turned off).
TEST(ViewHtml, SaysSoWhenTheBrowserHasNoWebgl) {
  const auto scene = load_scene({kGroundWall}, MaterialAssignment{});
  const std::string page = io::view_html(ground_wall_view(scene), "/* three */", "/* orbit */");
  const size_t probe = page.find("getContext('webgl')"), renderer = page.find("new THREE.WebGLRenderer(");
  ASSERT_NE(probe, std::string::npos);
  ASSERT_NE(renderer, std::string::npos);
  EXPECT_LT(probe, renderer);
  EXPECT_NE(page.find("This browser cannot draw the 3-D view: WebGL is not available"), std::string::npos);
  EXPECT_NE(page.find("note.id = 'nowebgl'"), std::string::npos);
  EXPECT_NE(page.find("body.dataset.status = 'no-webgl'"), std::string::npos);
  // The path table is filled before the page returns for want of a renderer.
  EXPECT_LT(page.find("table.appendChild(tr)"), page.find("if (!renderer) {"));
  // The message is styled so that it shows on the dark background.
  EXPECT_NE(page.find("#nowebgl {"), std::string::npos);
}

TEST(ViewHtml, ScriptEndTagsInTextCannotBreakThePage) {
  const auto scene = load_scene({kGroundWall}, MaterialAssignment{});
  io::ViewInput in = ground_wall_view(scene);
  in.title = "a</script><b>x";
  in.tags[0].name = "t</SCRIPT>";
  const std::string page = io::view_html(in, "var s = '</script>';", "");
  EXPECT_EQ(page.find("</script><b>"), std::string::npos);
  EXPECT_EQ(page.find("t</SCRIPT>"), std::string::npos);
  EXPECT_EQ(page.find("var s = '</script>'"), std::string::npos);
  EXPECT_NE(page.find("var s = '<\\/script>'"), std::string::npos);
  const nlohmann::json j = embedded_data(page);
  EXPECT_EQ(j["title"], "a</script><b>x");  // "<\/" reads back as "</"
  EXPECT_EQ(j["tags"][0]["name"], "t</SCRIPT>");
  EXPECT_NE(page.find("<title>rfidray view: a&lt;/script&gt;&lt;b&gt;x</title>"), std::string::npos);
}

TEST(ViewHtml, MissingThreeJsIsAnInputErrorAndWritesNothing) {
  const auto scene = load_scene({kGroundWall}, MaterialAssignment{});
  const testing::ScratchDir dir("view_html");
  const auto out = dir / "view.html";
  io::ThreeJsFiles files;
  files.three = "/nonexistent/three.min.js";
  try {
    io::write_view_html(out, ground_wall_view(scene), files);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/three.min.js: cannot read three.js (no such file)"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("apt-get install libjs-three"), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace rfidray
