// The export-mjcf command
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

// export-mjcf: the document to stdout, or whole to a file; a bad model or an unwritable path
// exits 2 with one line and leaves no file
TEST(TestbedCli, ExportMjcf) {
  const Outcome out = testbed("export-mjcf pinocchio");
  EXPECT_EQ(out.status, 0);
  EXPECT_EQ(out.output.rfind("<!-- pinocchio", 0), 0u);
  EXPECT_NE(out.output.find("<mujoco model=\"pinocchio\">"), std::string::npos);
  EXPECT_NE(out.output.find("</mujoco>\n"), std::string::npos);
  const fs::path folder = fresh_folder("export");
  fs::create_directories(folder);
  const fs::path file = folder / "pinocchio.xml";
  EXPECT_EQ(testbed("export-mjcf pinocchio -o " + file.string()).status, 0);
  EXPECT_TRUE(fs::exists(file));
  EXPECT_EQ(fs::file_size(file), out.output.size());
  expect_bad("export-mjcf /no/such/model.json -o " + (folder / "x.xml").string(),
             "/no/such/model.json: cannot open");
  EXPECT_FALSE(fs::exists(folder / "x.xml"));
  expect_bad("export-mjcf pinocchio -o /no/such/folder/x.xml", "/no/such/folder/x.xml");
  // what export-mjcf writes, validate takes, up to MJCF's depth; past it export refuses
  for (const char* chain : {"chain:1", "chain:2", "chain:96"}) {
    const fs::path xml = folder / "chain.xml";
    ASSERT_EQ(testbed(std::string("export-mjcf ") + chain + " -o " + xml.string()).status, 0);
    const Outcome back = testbed("validate " + xml.string());
    EXPECT_EQ(back.status, 0) << chain << "\n" << back.output;
    EXPECT_NE(back.output.find(std::string("model \"") + chain + "\""), std::string::npos);
  }
  expect_bad("export-mjcf chain:97 -o " + (folder / "deep.xml").string(), "97 segments deep");
  EXPECT_FALSE(fs::exists(folder / "deep.xml"));
  expect_bad("run --solver mujoco --mujoco-integrator rk5", "--mujoco-integrator");
}

}  // namespace
}  // namespace puppet::cli_test
