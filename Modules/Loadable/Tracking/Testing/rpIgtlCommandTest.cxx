// PlusServer's commands on our OpenIGTLink server, from a client that behaves as Slicer's
// OpenIGTLinkIF/OpenIGTLinkRemote do: a first STATUS with header v2 (so the server answers with
// v3 framing), COMMAND with MRMLNodeName metadata (→ RTS_COMMAND with Status/Message metadata)
// and the older STRING CMD_<uid> (→ STRING ACK_<uid> with <CommandReply .../>); StartRecording /
// StopRecording write a PLUS sequence file read back by rpPlusSequenceFile.
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "rpIgtlCommands.h"
#include "rpIgtlProtocol.h"
#include "rpIgtlServer.h"
#include "rpPlusSequenceFile.h"
#include "rpTrackingTestHelpers.h"

namespace {

struct Reply {
  rp::igtl::Header Header;
  std::vector<uint8_t> Body;
  std::string Meta(const char* key) const {
    rp::igtl::Body split;
    if (rp::igtl::SplitBody(this->Header, this->Body.data(), split) != rp::igtl::Status::Ok) return "";
    uint32_t size = 0;
    const char* v = split.Find(key, size);
    return v ? std::string(v, size) : "";
  }
  rp::igtl::Body Split() const {
    rp::igtl::Body split;
    rp::igtl::SplitBody(this->Header, this->Body.data(), split);
    return split;
  }
};

// Slicer's OpenIGTLinkIF as a raw client (rpTrackingTestHelpers), with the messages kept whole.
class SlicerLikeClient {
 public:
  explicit SlicerLikeClient(int port) : Client(port), Connected(Client.Connected()) {}
  void Send(const std::vector<uint8_t>& m) { ASSERT_TRUE(this->Client.Send(m)); }
  /// The next message of `type` (keep-alives and poses are passed over), within 5 s.
  bool Next(const char* type, Reply& out) { return this->Client.Next(type, out.Header, out.Body); }

 private:
  rp::test::IgtlTestClient Client;

 public:
  const bool Connected;
};

std::vector<uint8_t> Command(uint32_t id, const std::string& name, const std::string& xml) {
  std::vector<uint8_t> content(rp::igtl::CommandHeaderSize + xml.size());
  rp::igtl::EncodeCommand(id, name.c_str(), xml.data(), xml.size(), content.data());
  return rp::igtl::BuildMessage(2, "COMMAND", "CMD", rp::WallSeconds(), content.data(), content.size(), {{"MRMLNodeName", "CMD"}}, id);
}

std::vector<uint8_t> StringCommand(const std::string& uid, const std::string& xml) {
  std::vector<uint8_t> content(rp::igtl::StringHeaderSize + xml.size());
  rp::igtl::EncodeString(xml.data(), xml.size(), content.data());
  return rp::igtl::BuildMessage(1, "STRING", ("CMD_" + uid).c_str(), rp::WallSeconds(), content.data(), content.size());
}

std::string StringText(const Reply& r) {
  const rp::igtl::Body b = r.Split();
  uint16_t encoding = 0;
  const char* text = nullptr;
  size_t length = 0;
  if (rp::igtl::DecodeString(b.Content, b.ContentSize, encoding, text, length) != rp::igtl::Status::Ok) return "";
  return std::string(text, length);
}

class IgtlCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    this->Slot = this->Table.FindOrAdd("StylusToTracker");
    rp::IgtlServer::Options o;
    o.Port = 0;
    o.KeepAliveSeconds = 0.05;
    std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
    o.RecordFolder = ROBOPLAN_TEST_OUTPUT_DIR;  // StartRecording's OutputFilename is a name in it
    o.Transforms = [](const std::string& from, const std::string& to, double m[16], rp::ToolState& state) {
      if (from != "StylusTip" || to != "Reference") return false;
      for (int i = 0; i < 16; ++i) m[i] = i % 5 == 0 ? 1 : 0;
      m[3] = 42;
      state = rp::ToolState::OK;
      return true;
    };
    this->Server = std::make_unique<rp::IgtlServer>(this->Table, o);
    std::string error;
    ASSERT_TRUE(this->Server->Start(error)) << error;
  }
  rp::ToolPoseTable Table;
  int Slot = -1;
  std::unique_ptr<rp::IgtlServer> Server;
};

}  // namespace

TEST_F(IgtlCommands, CommandIsAnsweredWithRtsCommandCarryingStatusAndMessageMetadata) {
  SlicerLikeClient client(this->Server->Port());
  ASSERT_TRUE(client.Connected);
  // Slicer's connector: a first STATUS in header v2 so that the server talks v2 back.
  std::vector<uint8_t> status(rp::igtl::StatusSize(""));
  rp::igtl::EncodeStatus(rp::igtl::StatusOk, 0, "", "", status.data());
  client.Send(rp::igtl::BuildMessage(2, "STATUS", "", rp::WallSeconds(), status.data(), status.size()));
  client.Send(Command(7, "RequestChannelIds", "<Command Name=\"RequestChannelIds\" />"));
  Reply r;
  ASSERT_TRUE(client.Next("RTS_COMMAND", r));
  EXPECT_EQ(r.Header.Version, 2);
  EXPECT_EQ(r.Meta("Status"), "SUCCESS");
  EXPECT_EQ(r.Meta("Message"), "TrackerStream");
  const rp::igtl::Body b = r.Split();
  EXPECT_EQ(b.MessageId, 7u);
  uint32_t id = 0;
  char name[rp::igtl::CommandNameSize + 1];
  const char* text = nullptr;
  size_t length = 0;
  ASSERT_EQ(rp::igtl::DecodeCommand(b.Content, b.ContentSize, id, name, text, length), rp::igtl::Status::Ok);
  EXPECT_EQ(id, 7u);
  EXPECT_STREQ(name, "RequestChannelIds");
  EXPECT_EQ(std::string(text, length), "<CommandReply Status=\"SUCCESS\" Message=\"TrackerStream\" />");

  client.Send(Command(8, "GetTransform", "<Command Name=\"GetTransform\" TransformName=\"StylusTipToReference\" />"));
  ASSERT_TRUE(client.Next("RTS_COMMAND", r));
  EXPECT_EQ(r.Meta("Status"), "SUCCESS");
  EXPECT_EQ(r.Meta("Message").substr(0, 9), "1 0 0 42 ");
  client.Send(Command(9, "Teleport", "<Command Name=\"Teleport\" />"));
  ASSERT_TRUE(client.Next("RTS_COMMAND", r));
  EXPECT_EQ(r.Meta("Status"), "FAIL");
  EXPECT_NE(r.Meta("Message").find("unknown command Teleport"), std::string::npos) << r.Meta("Message");
  client.Send(Command(10, "X", "<Command Name=\"Unclosed"));
  ASSERT_TRUE(client.Next("RTS_COMMAND", r));
  EXPECT_EQ(r.Meta("Status"), "FAIL");
}

TEST_F(IgtlCommands, StringCmdIsAnsweredWithAckAndRecordingWritesAPlusSequence) {
  SlicerLikeClient client(this->Server->Port());
  ASSERT_TRUE(client.Connected);
  const std::string file = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/server-recording.igs.mha";
  std::filesystem::remove(file);
  client.Send(StringCommand("1", "<Command Name=\"StartRecording\" OutputFilename=\"server-recording.igs.mha\" />"));
  Reply r;
  ASSERT_TRUE(client.Next("STRING", r));
  EXPECT_STREQ(r.Header.DeviceName, "ACK_1");
  EXPECT_EQ(StringText(r).rfind("<CommandReply Status=\"SUCCESS\"", 0), 0u) << StringText(r);
  for (int i = 0; i < 5; ++i) {
    rp::ToolPose p;
    p.Translation[0] = 10.0 * i;
    p.State = i == 2 ? rp::ToolState::Missing : rp::ToolState::OK;
    this->Table.Publish(this->Slot, p);
    usleep(40000);  // the server sends (and records) at 60 Hz
  }
  client.Send(StringCommand("2", "<Command Name=\"StopRecording\" />"));
  ASSERT_TRUE(client.Next("STRING", r));
  EXPECT_STREQ(r.Header.DeviceName, "ACK_2");
  EXPECT_NE(StringText(r).find("frames successful to file " + file), std::string::npos) << StringText(r);
  const rp::PlusSequence s = rp::ReadPlusSequence(file);
  ASSERT_EQ(s.TransformNames, std::vector<std::string>{"StylusToTracker"});
  ASSERT_GE(s.Frames.size(), 4u);
  EXPECT_EQ(s.Frames.back().Transforms[0].Matrix[3], 40.0);
  bool missing = false;
  for (const auto& f : s.Frames) missing |= f.Transforms[0].State == rp::ToolState::Missing;
  EXPECT_TRUE(missing);
  client.Send(StringCommand("3", "<Command Name=\"StopRecording\" />"));
  ASSERT_TRUE(client.Next("STRING", r));
  EXPECT_EQ(StringText(r), "<CommandReply Status=\"FAIL\" Message=\"not recording\" />");
}

// Every hostile OutputFilename over the wire (STRING CMD_, as PLUS's own clients send it): each
// refused with a reply naming why, or (a name that exists) recorded under a new name; no file
// outside the recording folder is created or changed, an existing recording is never opened.
// (OutputFilename="" is PLUS's "no name": Recording.igs.mha, as a missing attribute.)
TEST_F(IgtlCommands, HostileOutputFilenamesAreRefusedOrMadeUniqueNeverOverwritten) {
  namespace fs = std::filesystem;
  const fs::path folder = ROBOPLAN_TEST_OUTPUT_DIR, outside = folder / "outside";
  fs::remove_all(outside);
  fs::create_directories(outside);
  for (const char* name : {"existing.igs.mha", "link.igs.mha", "dangling.igs.mha"}) fs::remove(folder / name);
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().filename().string().rfind("existing_", 0) == 0) fs::remove(entry.path());
  { std::ofstream(outside / "victim.igs.mha") << "victim"; }
  { std::ofstream(folder / "existing.igs.mha") << "an earlier recording"; }
  fs::create_symlink(outside / "victim.igs.mha", folder / "link.igs.mha");
  fs::create_symlink(outside / "created-through-a-link.igs.mha", folder / "dangling.igs.mha");
  SlicerLikeClient client(this->Server->Port());
  ASSERT_TRUE(client.Connected);
  const std::pair<std::string, std::string> hostile[] = {
      {(outside / "victim.igs.mha").string(), "is an absolute path"},
      {"../outside/victim.igs.mha", "has a '..' part"},
      {"recordings/../../outside/victim.igs.mha", "has a '..' part"},
      {"outside/x.igs.mha", "names a folder"},
      {"link.igs.mha", "is a symbolic link"},
      {"dangling.igs.mha", "is a symbolic link"},
      {"C:\\PlusApp\\Output\\x.igs.mha", "is a Windows path"},
      {"x.txt", "is not a PLUS sequence file"},
      {"x&#10;y.igs.mha", "control character"},
      {".x.igs.mha", "is hidden"},
  };
  int uid = 100;
  Reply r;
  for (const auto& [name, why] : hostile) {
    client.Send(StringCommand(std::to_string(++uid), "<Command Name=\"StartRecording\" OutputFilename=\"" + name + "\" />"));
    ASSERT_TRUE(client.Next("STRING", r)) << name;
    EXPECT_EQ(StringText(r).rfind("<CommandReply Status=\"FAIL\"", 0), 0u) << name << ": " << StringText(r);
    EXPECT_NE(StringText(r).find(why), std::string::npos) << name << ": " << StringText(r);
  }
  // A name that exists: recorded beside it under PLUS's date-and-time name, said in the reply.
  client.Send(StringCommand(std::to_string(++uid), "<Command Name=\"StartRecording\" OutputFilename=\"existing.igs.mha\" />"));
  ASSERT_TRUE(client.Next("STRING", r));
  EXPECT_EQ(StringText(r).rfind("<CommandReply Status=\"SUCCESS\" Message=\"Recording to " + (folder / "existing_").string(), 0), 0u)
      << StringText(r);
  EXPECT_NE(StringText(r).find("existing.igs.mha exists in the recording folder: kept, not overwritten"), std::string::npos)
      << StringText(r);
  client.Send(StringCommand(std::to_string(++uid), "<Command Name=\"StartRecording\" OutputFilename=\"other.igs.mha\" />"));
  ASSERT_TRUE(client.Next("STRING", r));
  EXPECT_NE(StringText(r).find("FAIL\" Message=\"already recording to " + (folder / "existing_").string()), std::string::npos)
      << StringText(r);
  rp::ToolPose p;
  p.State = rp::ToolState::OK;
  for (int i = 0; i < 5; ++i) {
    p.Translation[1] = i;
    this->Table.Publish(this->Slot, p);
    usleep(40000);
  }
  client.Send(StringCommand(std::to_string(++uid), "<Command Name=\"StopRecording\" />"));
  ASSERT_TRUE(client.Next("STRING", r));
  const std::string stopped = StringText(r);
  const size_t at = stopped.find("successful to file ");
  ASSERT_NE(at, std::string::npos) << stopped;
  const std::string written = stopped.substr(at + 19, stopped.find('"', at) - at - 19);
  EXPECT_EQ(fs::path(written).parent_path(), folder);
  EXPECT_GE(rp::ReadPlusSequence(written).Frames.size(), 3u);
  // Nothing outside changed, nothing was created through a link, the earlier recording is intact.
  std::ifstream victim(outside / "victim.igs.mha"), existing(folder / "existing.igs.mha");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(victim), {}), "victim");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(existing), {}), "an earlier recording");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(outside)) files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1);
}

TEST(IgtlCommandRegistry, HasPlusServerCommandsEachRegisteredOnce) {
  const std::vector<std::string> names = rp::IgtlCommandNames();
  for (const char* n : {"RequestChannelIds", "RequestDeviceIds", "StartRecording", "StopRecording", "GetTransform", "UpdateTransform"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  // What each may do: the ones that change what clients see or write files are only for the
  // server's command clients.
  for (const auto& [name, changes] : std::vector<std::pair<std::string, bool>>{{"RequestChannelIds", false},
                                                                               {"RequestDeviceIds", false},
                                                                               {"GetTransform", false},
                                                                               {"StartRecording", true},
                                                                               {"StopRecording", true},
                                                                               {"UpdateTransform", true}}) {
    rp::IgtlCommandAccess access = rp::IgtlCommandAccess::ReadOnly;
    ASSERT_TRUE(rp::IgtlCommandAccessOf(name, access)) << name;
    EXPECT_EQ(access == rp::IgtlCommandAccess::ChangesState, changes) << name;
  }
}
