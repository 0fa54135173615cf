// The parameter file: what --print-config writes loads back unchanged, and every kind of bad
// line is an error naming the file, the line and the key.
#include <gtest/gtest.h>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/parameter_file.hpp"

namespace rp = roadcross::preprocess;

namespace {

std::string error_of(const std::string& text) {
  rp::Parameters p;
  try {
    rp::parse_parameter_text(text, "test.ini", p);
  } catch (const rp::ParameterError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ParameterFile, PrintedDefaultsLoadBackToTheSameValues) {
  rp::Parameters changed;
  changed.context.crossing_points = 100;
  changed.context.motorway_points = -50;
  changed.suitability.threshold = 17.5;
  const std::string text = rp::format_parameter_file(changed);
  rp::Parameters loaded;
  rp::parse_parameter_text(text, "printed", loaded);
  EXPECT_EQ(rp::format_parameter_file(loaded), text);
  EXPECT_EQ(loaded.context.crossing_points, 100);
  EXPECT_EQ(loaded.suitability.threshold, 17.5);
  // Every parameter appears once, under its section.
  for (const rp::ParameterSpec& spec : loaded.specs()) {
    EXPECT_NE(text.find("\n" + spec.name + " = "), std::string::npos) << spec.key();
    EXPECT_NE(text.find("[" + spec.section + "]"), std::string::npos) << spec.key();
  }
}

TEST(ParameterFile, SectionsDottedKeysAndComments) {
  rp::Parameters p;
  rp::parse_parameter_text(
      "# comment\n; ini comment\n\ncontext.crossing_points = 12\n[suitability]\n"
      "threshold = 18 # trailing\n  valid_distance_m=7.5  \n",
      "t", p);
  EXPECT_EQ(p.context.crossing_points, 12);
  EXPECT_EQ(p.suitability.threshold, 18);
  EXPECT_EQ(p.suitability.valid_distance_m, 7.5);
  EXPECT_EQ(p.segments.max_segment_length_m, 10);  // untouched
}

TEST(ParameterFile, ErrorsNameFileLineAndKey) {
  EXPECT_EQ(error_of("[context]\ncrossing_pts = 3\n"),
            "test.ini:2: context.crossing_pts: unknown parameter (roadcross-build --print-config "
            "lists them all)");
  EXPECT_NE(error_of("[contxt]\n").find("test.ini:1: [contxt]: unknown section"),
            std::string::npos);
  EXPECT_EQ(error_of("\n[context]\ncrossing_points = ten\n"),
            "test.ini:3: context.crossing_points: 'ten' is not a number");
  EXPECT_EQ(error_of("[context]\ncrossing_points = 2.5\n"),
            "test.ini:2: context.crossing_points: 2.5 is not a whole number");
  EXPECT_EQ(error_of("[segments]\nmax_segment_length_m = 0\n"),
            "test.ini:2: segments.max_segment_length_m: 0 is out of range [0.1, 1000]");
  EXPECT_EQ(error_of("[segments]\nmax_segment_length_m = 5\nmax_segment_length_m = 6\n"),
            "test.ini:3: segments.max_segment_length_m: given twice");
  EXPECT_EQ(error_of("[context]\njust words\n"),
            "test.ini:2: expected 'name = value' or '[section]'");
  EXPECT_EQ(error_of("[context]\ncrossing_points = \n"),
            "test.ini:2: context.crossing_points: '' is not a number");
  EXPECT_EQ(error_of("[context]\ncrossing_points = nan\n"),
            "test.ini:2: context.crossing_points: 'nan' is not a number");
  EXPECT_EQ(error_of("max_segment_length_m = 5\n"),
            "test.ini:1: max_segment_length_m: unknown parameter (roadcross-build --print-config "
            "lists them all)");
}

TEST(ParameterFile, ShippedProfilesLoad) {
  for (const char* name : {"thesis-text.ini", "thesis-code.ini"}) {
    SCOPED_TRACE(name);
    rp::Parameters p;
    rp::read_parameter_file(std::string(ROADCROSS_TEST_DATA_DIR) + "/../../docs/profiles/" + name,
                            p);
    p.validate();
    EXPECT_EQ(p.context.minor_points, 0);  // the thesis gives other classes nothing
    if (std::string(name) == "thesis-text.ini") {
      EXPECT_EQ(p.context.crossing_points, 10);
      EXPECT_EQ(p.context.motorway_points, -10);
    } else {
      EXPECT_EQ(p.context.crossing_points, 100);
      EXPECT_EQ(p.context.motorway_points, -50);
    }
  }
}

TEST(ParameterFile, RobotProfilesLoad) {
  // The values the profiles' comments derive from their sources (docs/profiles/*.ini).
  struct Expected {
    const char* name;
    double max_kerb_height_m, crossing_speed_mps, sensor_height_m;
  };
  for (const Expected& e :
       {Expected{"delivery-robot.ini", 0.04, 1.67, 0.55}, Expected{"husky.ini", 0.10, 1.0, 0.39},
        Expected{"spot.ini", 0.30, 1.6, 0.84}}) {
    SCOPED_TRACE(e.name);
    rp::Parameters p;
    rp::read_parameter_file(std::string(ROADCROSS_TEST_DATA_DIR) + "/../../docs/profiles/" + e.name,
                            p);
    p.validate();
    EXPECT_DOUBLE_EQ(p.suitability.max_kerb_height_m, e.max_kerb_height_m);
    EXPECT_DOUBLE_EQ(p.sight.crossing_speed_mps, e.crossing_speed_mps);
    EXPECT_DOUBLE_EQ(p.sight.sensor_height_m, e.sensor_height_m);
    EXPECT_EQ(p.context.crossing_points, rp::Parameters{}.context.crossing_points);  // untouched
  }
}

TEST(ParameterFile, MissingFile) {
  rp::Parameters p;
  EXPECT_THROW(rp::read_parameter_file("/nonexistent/roadcross.ini", p), rp::ParameterError);
}

}  // namespace
