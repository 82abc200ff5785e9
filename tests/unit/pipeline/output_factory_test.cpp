// The outputs built from the service config by name (app/pipeline/output_factory.hpp).
#include "app/pipeline/output_factory.hpp"

#include <gtest/gtest.h>

#include "support/test_data.hpp"

namespace probeless {
namespace {

TEST(OutputFactory, EachSectionOffGivesNoOutput) {
  ServiceConfig config;
  config.http.enabled = false;
  for (const std::string_view name : kOutputNames)
    EXPECT_EQ(make_output(name, config), nullptr) << name;
  EXPECT_THROW(make_output("hdmi", config), std::invalid_argument);
}

TEST(OutputFactory, OutputsSayWhatTheyNeed) {
  ServiceConfig config = parse_service_config("[http]\nport = 0\njpeg_quality = 70\n");
  auto http = make_output("http", config);
  ASSERT_NE(http, nullptr);
  EXPECT_EQ(http->name(), "http");
  EXPECT_TRUE(http->needs().jpeg);
  EXPECT_EQ(http->needs().jpeg_quality, 70);
  EXPECT_TRUE(http->url().starts_with("http://127.0.0.1:"));
  http->stop();

  config.files.dir = testing::scratch_dir();
  auto files = make_output("files", config);
  ASSERT_NE(files, nullptr);
  EXPECT_EQ(files->name(), "files");
  EXPECT_FALSE(files->needs().jpeg) << "the files encode their own JPEG, at their own quality";
  EXPECT_TRUE(files->needs().colour);
  EXPECT_FALSE(files->needs().matte);
  config.files.write_matte = true;
  EXPECT_TRUE(make_output("files", config)->needs().matte);
  nlohmann::json status;
  files->add_status(status);
  EXPECT_EQ(status["file_output"]["written"], 0);
  files->stop();
}

}  // namespace
}  // namespace probeless
