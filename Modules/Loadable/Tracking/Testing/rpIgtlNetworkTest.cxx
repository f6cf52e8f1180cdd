// Serving a lab's network safely (issue 39), with 127.0.0.2 standing for another machine (a
// second loopback address: network tests stay on 127.0.0.0/8):
//  * the server listens on the address it is given only;
//  * every client gets the stream and the read-only commands; UpdateTransform, StartRecording and
//    StopRecording from a client outside --command-clients get a FAIL reply naming why and change
//    nothing; an allowed client's succeed; every command is logged with the client's address and
//    its result;
//  * end to end: `roboplan track --plus-config ... --serve` (PlusServer's configuration on the
//    simulator) with upstream OpenIGTLink 3.x as both clients, each a second process
//    (rpUpstreamIgtlClient), the refused one from 127.0.0.2 asking for the stylus calibration to
//    change and for an existing file elsewhere to be overwritten.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "rpAtomicFile.h"
#include "rpIgtlProtocol.h"
#include "rpIgtlServer.h"
#include "rpNetworkAddress.h"
#include "rpPlusSequenceFile.h"
#include "rpSharedData.h"
#include "rpTestOutput.h"
#include "rpTestTime.h"
#include "rpTrackingCommands.h"
#include "rpTrackingTestHelpers.h"

namespace fs = std::filesystem;
using namespace rp;

namespace {

std::string ReadText(const fs::path& path) {
  std::string text, error;
  return rp::ReadFile(path.string(), text, error) ? text : "(unreadable: " + error + ")";
}

using ClientFrom = test::IgtlTestClient;  // (port, from, to)

// The server's session log lines, collected from its thread.
struct LogLines {
  std::mutex Mutex;
  std::vector<std::string> Lines;
  std::function<void(const std::string&)> Sink() {
    return [this](const std::string& line) {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Lines.push_back(line);
    };
  }
  std::string Text() {
    std::lock_guard<std::mutex> lock(this->Mutex);
    std::string text;
    for (const auto& l : this->Lines) text += l + "\n";
    return text;
  }
};

}  // namespace

TEST(IgtlNetwork, AddressesAndNetworksAsALabWritesThem) {
  Ipv4 a = 0;
  std::string error;
  ASSERT_TRUE(ParseBindAddress("all", a, error));
  EXPECT_EQ(a, 0u);
  ASSERT_TRUE(ParseBindAddress("192.168.10.5", a, error));
  EXPECT_EQ(FormatIpv4(a), "192.168.10.5");
  for (const char* bad : {"", "localhost", "192.168.10", "192.168.10.256", "1.2.3.4.5", "-1.2.3.4", "1..2.3", "::1"}) {
    EXPECT_FALSE(ParseBindAddress(bad, a, error)) << bad;
    EXPECT_NE(error.find("IPv4 address"), std::string::npos) << error;
  }
  AddressAllowList list;
  ASSERT_TRUE(list.Add("127.0.0.1, 192.168.10.0/24", error)) << error;
  ASSERT_TRUE(ParseIpv4("192.168.10.77", a, error));
  EXPECT_TRUE(list.Contains(a));
  ASSERT_TRUE(ParseIpv4("192.168.11.77", a, error));
  EXPECT_FALSE(list.Contains(a));
  ASSERT_TRUE(ParseIpv4("127.0.0.2", a, error));
  EXPECT_FALSE(list.Contains(a));  // 127.0.0.1 is one host, not the loopback network
  EXPECT_TRUE(AddressAllowList::Loopback().Contains(a));
  EXPECT_EQ(list.ToString(), "127.0.0.1, 192.168.10.0/24");
  EXPECT_FALSE(list.Add("10.0.0.0/33", error));
  EXPECT_NE(error.find("prefix length"), std::string::npos) << error;
  EXPECT_FALSE(list.Add("10.0.0.1,,", error));
  AddressAllowList nobody;
  ASSERT_TRUE(nobody.Add("none", error));
  EXPECT_EQ(nobody.ToString(), "nobody");
  ASSERT_TRUE(ParseIpv4("127.0.0.1", a, error));
  EXPECT_FALSE(nobody.Contains(a));
}

TEST(IgtlNetwork, TheServerListensOnTheAddressItIsGivenOnly) {
  ToolPoseTable table;
  IgtlServer::Options o;
  o.Port = 0;
  o.BindAddress = "127.0.0.3";
  IgtlServer server(table, o);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  ClientFrom there(server.Port(), "127.0.0.2", "127.0.0.3"), elsewhere(server.Port(), "127.0.0.2", "127.0.0.1");
  EXPECT_TRUE(there.Connected());
  EXPECT_FALSE(elsewhere.Connected());  // nothing listens on 127.0.0.1 at that port
  server.Stop();

  o.BindAddress = "192.168.300.1";
  IgtlServer bad(table, o);
  EXPECT_FALSE(bad.Start(error));
  EXPECT_NE(error.find("not an IPv4 address"), std::string::npos) << error;
  o.BindAddress = "127.0.0.1";
  o.RecordFolder = (fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "no-such-folder").string();
  IgtlServer noFolder(table, o);
  EXPECT_FALSE(noFolder.Start(error));
  EXPECT_NE(error.find("recording folder"), std::string::npos) << error;
}

// The policy on the server itself: a client from 127.0.0.2 (another machine) with 127.0.0.1 alone
// allowed to change state; the allowed client from 127.0.0.1.
TEST(IgtlNetwork, AClientNotAllowedGetsTheStreamAndReadOnlyCommandsAndAReplyNamingWhyForTheRest) {
  const fs::path dir = rptest::TestDir("policy");
  const fs::path victim = dir / "victim.igs.mha";
  { std::ofstream(victim) << "an earlier recording\n"; }
  ToolPoseTable table;
  const int slot = table.FindOrAdd("StylusToTracker");
  LogLines log;
  IgtlServer::Options o;
  o.Port = 0;
  o.KeepAliveSeconds = 0.05;
  std::string error;
  o.CommandClients = AddressAllowList();
  ASSERT_TRUE(o.CommandClients.Add("127.0.0.1", error)) << error;
  o.RecordFolder = (dir / "recordings").string();
  fs::create_directories(o.RecordFolder);
  o.Log = log.Sink();
  IgtlServer server(table, o);
  ASSERT_TRUE(server.Start(error)) << error;
  ToolPose pose;
  pose.State = ToolState::OK;
  pose.Translation[2] = 42;
  std::atomic<bool> publishing{true};
  std::thread tracker([&] {
    while (publishing) {
      table.Publish(slot, pose);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });

  ClientFrom other(server.Port(), "127.0.0.2", "127.0.0.1");
  ASSERT_TRUE(other.Connected());
  igtl::Header h;
  std::vector<uint8_t> body;
  ASSERT_TRUE(other.Next("TRANSFORM", h, body)) << "the stream reaches a client that may not change state";
  EXPECT_STREQ(h.DeviceName, "StylusToTracker");
  std::string status, message;
  ASSERT_TRUE(other.Command("<Command Name=\"RequestDeviceIds\" />", status, message));
  EXPECT_EQ(status, "SUCCESS");
  const std::string update =
      "<Command Name=\"UpdateTransform\" TransformName=\"StylusTipToStylus\" TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" />";
  ASSERT_TRUE(other.Command(update, status, message));
  EXPECT_EQ(status, "FAIL");
  EXPECT_NE(message.find("UpdateTransform refused: client 127.0.0.2:"), std::string::npos) << message;
  EXPECT_NE(message.find("from 127.0.0.1 only"), std::string::npos) << message;
  ASSERT_TRUE(other.Command("<Command Name=\"GetTransform\" TransformName=\"StylusTipToStylus\" />", status, message));
  EXPECT_EQ(status, "FAIL") << "nothing was set: " << message;
  ASSERT_TRUE(other.Command("<Command Name=\"StartRecording\" OutputFilename=\"" + victim.string() + "\" />", status, message));
  EXPECT_EQ(status, "FAIL");
  EXPECT_NE(message.find("StartRecording refused"), std::string::npos) << message;
  ASSERT_TRUE(other.Command("<Command Name=\"StopRecording\" />", status, message));
  EXPECT_NE(message.find("StopRecording refused"), std::string::npos) << message;

  ClientFrom local(server.Port(), "127.0.0.1", "127.0.0.1");
  ASSERT_TRUE(local.Connected());
  ASSERT_TRUE(local.Command(update, status, message));
  EXPECT_EQ(status, "SUCCESS") << message;
  ASSERT_TRUE(other.Command("<Command Name=\"GetTransform\" TransformName=\"StylusTipToStylus\" />", status, message));
  EXPECT_EQ(status, "SUCCESS");
  EXPECT_EQ(message.substr(0, 24), "1 0 0 0 0 1 0 0 0 0 1 -1") << message;
  ASSERT_TRUE(local.Command("<Command Name=\"StartRecording\" OutputFilename=\"session.igs.mha\" />", status, message));
  EXPECT_EQ(status, "SUCCESS") << message;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(local.Command("<Command Name=\"StopRecording\" />", status, message));
  EXPECT_EQ(status, "SUCCESS") << message;
  EXPECT_NE(message.find("frames successful to file " + (fs::path(o.RecordFolder) / "session.igs.mha").string()), std::string::npos)
      << message;
  publishing = false;
  tracker.join();
  server.Stop();

  EXPECT_EQ(ReadText(victim), "an earlier recording\n");
  const PlusSequence recorded = ReadPlusSequence((fs::path(o.RecordFolder) / "session.igs.mha").string());
  ASSERT_GE(recorded.Frames.size(), 3u);
  EXPECT_EQ(recorded.Frames[0].Transforms[0].Matrix[11], 42.0);
  // The session log: each connection, each command with its client, command and result.
  const std::string text = log.Text();
  EXPECT_NE(text.find("client 127.0.0.2:"), std::string::npos) << text;
  EXPECT_NE(text.find("connected (stream and read-only commands)"), std::string::npos) << text;
  EXPECT_NE(text.find("connected (may change state)"), std::string::npos) << text;
  EXPECT_EQ(test::Count(text, "command from 127.0.0.2:"), 6u) << text;
  EXPECT_EQ(test::Count(text, "command from 127.0.0.1:"), 3u) << text;
  EXPECT_NE(text.find(": UpdateTransform TransformName=\"StylusTipToStylus\" TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" -> "
                      "FAIL: UpdateTransform refused: client 127.0.0.2:"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(": StartRecording OutputFilename=\"" + victim.string() + "\" -> FAIL: StartRecording refused"), std::string::npos)
      << text;
  EXPECT_NE(text.find(": UpdateTransform TransformName=\"StylusTipToStylus\" TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" -> "
                      "SUCCESS: Transform StylusTipToStylus updated."),
            std::string::npos)
      << text;
}

#if ROBOPLAN_UPSTREAM_IGTL

namespace {
// One upstream client process; its printed lines.
std::vector<std::string> RunUpstreamClient(const std::string& from, int port, const std::vector<std::string>& actions,
                                           const fs::path& output) {
  std::vector<std::string> arguments = {ROBOPLAN_UPSTREAM_IGTL_CLIENT, "--from", from, "--to", "127.0.0.1", "--port",
                                        std::to_string(port)};
  arguments.insert(arguments.end(), actions.begin(), actions.end());
  test::ChildProcess child;
  std::string error;
  EXPECT_TRUE(child.Start(arguments, output.string(), error)) << error;
  EXPECT_TRUE(child.WaitExit(rptest::WaitSeconds(30))) << "the upstream client did not finish";
  std::vector<std::string> lines;
  std::istringstream in(child.Output());
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool Has(const std::vector<std::string>& lines, const std::string& prefix) {
  for (const auto& l : lines)
    if (l.rfind(prefix, 0) == 0) return true;
  return false;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

double TipZ(const std::vector<std::string>& lines, size_t nth) {
  size_t seen = 0;
  for (const auto& l : lines) {
    if (l.rfind("TRANSFORM StylusTipToReference ", 0) != 0) continue;
    if (seen++ < nth) continue;
    std::istringstream in(l);
    std::string word, name, status;
    double x = 0, y = 0, z = 0;
    in >> word >> name >> status >> x >> y >> z;
    return z;
  }
  return NAN;
}
}  // namespace

// The scenario, end to end: PlusServer's configuration served by `roboplan track`; from
// "another machine" (127.0.0.2) upstream OpenIGTLink asks to change the stylus calibration and to
// record over an existing file elsewhere: both refused, named, logged, nothing changed. The same
// client program from 127.0.0.1 (allowed): the calibration changes the served tip, a recording
// is written into --record-dir.
TEST(IgtlNetwork, TrackServesAnotherMachineWithUpstreamClientsRefusedAndAllowed) {
  const std::string config = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data/ConfigFiles/PlusDeviceSet_Server_NDIPolaris.xml";
  RP_REQUIRE_SHARED_DATA(config);
  const fs::path dir = rptest::TestDir("two-machines");
  const fs::path victim = dir / "elsewhere" / "earlier.igs.mha";
  fs::create_directories(victim.parent_path());
  { std::ofstream(victim) << "an earlier recording\n"; }
  fs::create_directories(dir / "recordings");
  const int port = test::FreePort();
  std::ostringstream out, err;
  int code = -1;
  std::thread track([&] {
    code = RunTrackCommand({"--plus-config", config, "--simulate", "--seconds", std::to_string(rptest::WaitSeconds(5)), "--serve", std::to_string(port), "--bind",
                            "127.0.0.1", "--command-clients", "127.0.0.1", "--record-dir", (dir / "recordings").string(), "--log",
                            (dir / "session.log").string()},
                           nullptr, out, err);
  });
  const std::string update =
      "<Command Name=\"UpdateTransform\" TransformName=\"StylusTipToStylus\" TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" />";
  const auto refused = RunUpstreamClient(
      "127.0.0.2", port,
      {"--wait", "StylusTipToReference", "--command", update, "--command",
       "<Command Name=\"StartRecording\" OutputFilename=\"" + victim.string() + "\" />", "--command",
       "<Command Name=\"StopRecording\" />", "--command", "<Command Name=\"GetTransform\" TransformName=\"StylusTipToStylus\" />"},
      dir / "client-127.0.0.2.txt");
  const auto allowed = RunUpstreamClient(
      "127.0.0.1", port,
      {"--wait", "StylusTipToReference", "--command", update, "--wait-change", "StylusTipToReference", "--command",
       "<Command Name=\"StartRecording\" OutputFilename=\"session.igs.mha\" />", "--sleep", "500", "--command",
       "<Command Name=\"StopRecording\" />"},
      dir / "client-127.0.0.1.txt");
  track.join();
  ASSERT_EQ(code, 0) << err.str();

  // The refused client: the stream, a FAIL naming why for each change, the read-only command.
  ASSERT_TRUE(Has(refused, "TRANSFORM StylusTipToReference OK ")) << Joined(refused);
  EXPECT_TRUE(Has(refused, "REPLY 101 FAIL UpdateTransform refused: client 127.0.0.2:")) << Joined(refused);
  EXPECT_TRUE(Has(refused, "REPLY 102 FAIL StartRecording refused: client 127.0.0.2:")) << Joined(refused);
  EXPECT_TRUE(Has(refused, "REPLY 103 FAIL StopRecording refused: client 127.0.0.2:")) << Joined(refused);
  EXPECT_TRUE(Has(refused, "REPLY 104 SUCCESS 1 0 0.000203823 0.0180449 ")) << "the calibration unchanged: " << Joined(refused);
  // The allowed client: the tip it sees before its update is where the refused one saw it; after
  // it, 100 - 88.53 mm further along the stylus.
  ASSERT_TRUE(Has(allowed, "REPLY 101 SUCCESS Transform StylusTipToStylus updated.")) << Joined(allowed);
  EXPECT_NEAR(TipZ(allowed, 0), TipZ(refused, 0), 0.5) << Joined(allowed) << Joined(refused);
  EXPECT_NEAR(TipZ(allowed, 1) - TipZ(allowed, 0), -(100 - 88.5321), 0.5) << Joined(allowed);
  const fs::path recording = dir / "recordings" / "session.igs.mha";
  EXPECT_TRUE(Has(allowed, "REPLY 102 SUCCESS Recording to " + recording.string() + " started.")) << Joined(allowed);
  EXPECT_TRUE(Has(allowed, "REPLY 103 SUCCESS Recording ")) << Joined(allowed);
  const PlusSequence s = ReadPlusSequence(recording.string());
  EXPECT_GE(s.Frames.size(), 10u);
  EXPECT_GE(s.TransformIndex("StylusTipToReference"), 0);
  EXPECT_EQ(ReadText(victim), "an earlier recording\n") << "the file elsewhere is untouched";

  // The session log (--log) and the terminal: each command with its client and result.
  const std::string log = ReadText(dir / "session.log");
  EXPECT_EQ(test::Count(log, "command from 127.0.0.2:"), 4u) << log;
  EXPECT_EQ(test::Count(log, "command from 127.0.0.1:"), 3u) << log;
  EXPECT_NE(log.find("UpdateTransform TransformName=\"StylusTipToStylus\" TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" -> "
                     "FAIL: UpdateTransform refused: client 127.0.0.2:"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("StartRecording OutputFilename=\"" + victim.string() + "\" -> FAIL: StartRecording refused"), std::string::npos)
      << log;
  EXPECT_NE(log.find("-> SUCCESS: Transform StylusTipToStylus updated."), std::string::npos) << log;
  EXPECT_NE(log.find("serving OpenIGTLink on 127.0.0.1:" + std::to_string(port)), std::string::npos) << log;
  EXPECT_NE(err.str().find("track: command from 127.0.0.2:"), std::string::npos) << err.str();
}

#else

TEST(IgtlNetwork, UpstreamClientsNeedTheOracle) {
  GTEST_SKIP() << "upstream OpenIGTLink 3.x not found at " << ROBOPLAN_UPSTREAM_IGTL_SOURCE
               << ": the two-machine test with upstream clients is skipped";
}

#endif
