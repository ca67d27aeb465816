// Output folders through the command (harness/src/output_folder.cpp): replaced whole or not at all,
// locked, never written through a link, a crash tidied by the next run
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

// A file the testbed writes (-o, --csv) is a new one or a regular file it replaces; a device,
// FIFO, folder or a link to one is refused before anything runs and left as it was
TEST(TestbedCli, OutputsNeverReplaceWhatIsNotOurs) {
  const fs::path folder = fresh_folder("not_ours");
  fs::create_directories(folder);
  ASSERT_EQ(::mkfifo((folder / "fifo").c_str(), 0644), 0);
  fs::create_directory(folder / "folder");
  fs::create_symlink("fifo", folder / "link_to_fifo");
  fs::create_symlink("missing", folder / "dangling");
  std::vector<std::string> refused = {"fifo", "folder", "link_to_fifo", "dangling"};
  if (::getuid() == 0) {  // a copy of /dev/null, as root would meet it
    ASSERT_EQ(::mknod((folder / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
    fs::create_symlink("null", folder / "link_to_null");
    refused.push_back("null");
    refused.push_back("link_to_null");
  }
  for (const std::string& name : refused) {
    const fs::file_status before = fs::symlink_status(folder / name);
    expect_bad("export-mjcf pinocchio -o " + (folder / name).string(), "-o: ");
    expect_bad("gate " + std::string(PUPPET_SOURCE_DIR) + "/results/bench/bench_step.json" +
                   " --csv " + (folder / name).string(),
               "--csv: ");
    EXPECT_EQ(fs::symlink_status(folder / name).type(), before.type()) << name;
  }
  // a regular file is replaced; a link, even to a regular file, is never written through
  std::ofstream(folder / "old.xml") << "old";
  ASSERT_EQ(testbed("export-mjcf chain:3 -o " + (folder / "old.xml").string()).status, 0);
  EXPECT_NE(slurp(folder / "old.xml").find("<mujoco model=\"chain:3\">"), std::string::npos);
  std::ofstream(folder / "victim.xml") << "victim";
  fs::create_symlink("victim.xml", folder / "link.xml");
  expect_bad("export-mjcf chain:3 -o " + (folder / "link.xml").string(),
             "is a symbolic link, which is never written through");
  EXPECT_TRUE(fs::is_symlink(folder / "link.xml"));
  EXPECT_EQ(slurp(folder / "victim.xml"), "victim");
  // standard output that cannot be written is a failure, not success
  for (const char* command : {"export-mjcf pinocchio", "validate pinocchio", "list"}) {
    const Outcome o = shell(std::string(TESTBED_BINARY) + " " + command + " 2>&1 >/dev/full");
    EXPECT_EQ(o.status, 1) << command << "\n" << o.output;
    EXPECT_NE(o.output.find("cannot write to standard output"), std::string::npos) << o.output;
  }
  fs::remove_all(folder);
}

// killed outright, a run leaves the old results and its staging folder beside them, which the
// next command on the folder removes
TEST(TestbedCli, ACrashLeavesTheOldResultsAndTheNextRunTidies) {
  const fs::path out = folder_with_results("crashed");
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(long_run(out));
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  ::kill(child.pid, SIGKILL);
  int status = 0;
  ASSERT_TRUE(child.wait(5.0, &status));
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_FALSE(leftovers(out).empty());  // its staging folder, and its lock file
  const Outcome next = testbed(
      "run --scenario spin --solver procedural --rule literal "
      "--duration 0.1 --no-accuracy --no-timing --out " +
      out.string());
  EXPECT_EQ(next.status, 0) << next.output;
  EXPECT_NE(read_all(out / "summary.csv").find("\nspin,"), std::string::npos);
  EXPECT_EQ(read_all(out / "summary.csv").find("\nhang,"), std::string::npos);  // no mix
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(out);
}

// a second command on a folder being written is refused at once, naming the first one, which
// goes on undisturbed
TEST(TestbedCli, ASecondCommandOnTheSameFolderIsRefused) {
  // the first command: one whose steps take seconds, so that it surely holds the folder when
  // the second one comes, however fast the machine
  const fs::path model = limited_chain(fresh_folder("contended_model"), 300, 1.0);
  const fs::path out = fresh_folder("contended");
  const Child first = start(long_step_run(model, out));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const Outcome second = testbed("run --scenario hang --duration 0.1 --out " + out.string());
  EXPECT_EQ(second.status, 2) << second.output;
  EXPECT_NE(second.output.find("is being written by another command (pid " +
                               std::to_string(first.pid) + ")"),
            std::string::npos)
      << second.output;
  // the first one was not disturbed: it runs on until it is stopped, and then tidies
  int status = -1;
  EXPECT_FALSE(first.wait(0.2, &status));
  ::kill(first.pid, SIGINT);
  ASSERT_TRUE(first.wait(5.0, &status));
  EXPECT_EQ(status, 128 + SIGINT);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(model.parent_path());
}

// A symbolic link planted at the lock's name is never written through: the command is refused
// in one line and the file it names keeps its bytes
TEST(TestbedCli, ALinkPlantedAtTheLockIsRefusedNotFollowed) {
  const fs::path root = fresh_folder("planted_lock");
  fs::create_directories(root);
  const fs::path victim = root / "victim.txt";
  write_text(victim, "precious");
  fs::create_symlink(victim, root / ".out.lock");
  expect_bad(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
          (root / "out").string(),
      "is a symbolic link, which is never written through");
  EXPECT_EQ(read_all(victim), "precious");
  EXPECT_FALSE(fs::exists(root / "out"));
  fs::remove_all(root);
}

// A folder name the file system allows but the staging name does not is refused before anything
// is made: the parent folders it would have needed are not left behind
TEST(TestbedCli, ATooLongFolderNameLeavesNothingBehind) {
  const fs::path root = fresh_folder("long_name");
  const fs::path out = root / "a" / "b" / std::string(250, 'n');
  expect_bad(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
          out.string(),
      "--out: ");
  EXPECT_FALSE(fs::exists(root));
  // a file name the file system allows (250 bytes) whose temporary name it would not
  fs::create_directories(root);
  expect_bad("export-mjcf chain:3 -o " + (root / std::string(250, 'f')).string(),
             "bytes; at most 229 (its temporary name is longer)");
  EXPECT_TRUE(fs::is_empty(root));
  fs::remove_all(root);
}

// a disk that fills up mid-run (here: no file may pass 4 kB) fails the run, which says so, and
// leaves the old results
TEST(TestbedCli, AFullDiskLeavesTheOldResults) {
  const fs::path out = folder_with_results("full");
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(
      {"run", "--scenario", "hang", "--solver", "procedural", "--rule", "literal", "--duration",
       "1", "--sample-hz", "0", "--no-accuracy", "--no-timing", "--out", out.string()},
      4096);
  int status = -1;
  ASSERT_TRUE(child.wait(60.0, &status));
  EXPECT_EQ(status, 1);
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(out);
}

}  // namespace
}  // namespace puppet::cli_test
