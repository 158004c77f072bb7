#include "discovery_state_keeper.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

namespace {

namespace fs = std::filesystem;

class DiscoveryStateKeeperTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ctsfleet-state-keeper-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& text) {
    std::ofstream out(state_file());
    out << text;
  }
  std::string read(const fs::path& file) const {
    std::ifstream in(file);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  fs::path state_file() const { return dir_ / "server-44-53-00-5f.json"; }

  fs::path dir_;
};

const std::string kFirst = R"({"participants": {"a": 1}})";
const std::string kSecond = R"({"participants": {"a": 1, "b": 2}})";

TEST_F(DiscoveryStateKeeperTest, AFileCutShortByACrashGetsItsLastCompleteVersionBack) {
  coordinator::DiscoveryStateKeeper keeper(dir_);
  write(kFirst);
  keeper.keep_complete_copies();
  write(kSecond);
  keeper.keep_complete_copies();
  write(kSecond.substr(0, kSecond.size() / 2));  // the server died while rewriting it
  keeper.keep_complete_copies();                 // a file cut short is never kept
  EXPECT_EQ(read(coordinator::complete_copy_of(state_file())), kSecond);
  EXPECT_EQ(keeper.restore_cut_short_files(), 1);
  EXPECT_EQ(read(state_file()), kSecond);
}

TEST_F(DiscoveryStateKeeperTest, ACompleteFileAndTheServersOtherFilesAreLeftAsTheyAre) {
  coordinator::DiscoveryStateKeeper keeper(dir_);
  write(kFirst);
  keeper.keep_complete_copies();
  write(kSecond);  // complete, not copied yet: the newest is what the server restarts on
  std::ofstream(dir_ / "server-44-53-00-5f_queue.json");  // empty, Fast DDS's unused queue file
  EXPECT_EQ(keeper.restore_cut_short_files(), 0);
  EXPECT_EQ(read(state_file()), kSecond);
  EXPECT_EQ(read(dir_ / "server-44-53-00-5f_queue.json"), "");
  EXPECT_FALSE(fs::exists(coordinator::complete_copy_of(dir_ / "server-44-53-00-5f_queue.json")));
}

TEST_F(DiscoveryStateKeeperTest, WithoutACompleteCopyTheFileCutShortStays) {
  coordinator::DiscoveryStateKeeper keeper(dir_);
  write("{\"participants\": {");
  keeper.keep_complete_copies();
  EXPECT_FALSE(fs::exists(coordinator::complete_copy_of(state_file())));
  EXPECT_EQ(keeper.restore_cut_short_files(), 0);
  EXPECT_EQ(read(state_file()), "{\"participants\": {");
}

TEST_F(DiscoveryStateKeeperTest, WhatTheServerReceivedIsForgottenWhatItSentIsKept) {
  coordinator::DiscoveryStateKeeper keeper(dir_);
  write(kSecond);
  std::ofstream(dir_ / "server-44-53-00-5f_reader.db") << "acknowledged up to 42";
  std::ofstream(dir_ / "server-44-53-00-5f_writer.db") << "sent up to 17";
  std::ofstream(dir_ / "notes_reader.db") << "not the server's";
  EXPECT_EQ(keeper.forget_what_the_server_received(), 1);
  EXPECT_FALSE(fs::exists(dir_ / "server-44-53-00-5f_reader.db"));
  EXPECT_EQ(read(dir_ / "server-44-53-00-5f_writer.db"), "sent up to 17");
  EXPECT_EQ(read(dir_ / "notes_reader.db"), "not the server's");
  EXPECT_EQ(read(state_file()), kSecond);
  EXPECT_EQ(keeper.forget_what_the_server_received(), 0);  // nothing left to forget: no error
}

TEST_F(DiscoveryStateKeeperTest, OneStateDirectoryServesOneServerAtATime) {
  auto first = std::make_unique<coordinator::DiscoveryStateKeeper>(dir_);
  try {
    coordinator::DiscoveryStateKeeper second(dir_);
    FAIL() << "a second keeper of the same directory was allowed";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("in use by another ctsfleet-discovery"), std::string::npos) << error.what();
  }
  first.reset();
  EXPECT_NO_THROW(coordinator::DiscoveryStateKeeper again(dir_));
}

}  // namespace
