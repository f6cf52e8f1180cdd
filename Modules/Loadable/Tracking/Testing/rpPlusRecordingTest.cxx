// Recordings that are safe (issue 39): PLUS sequences streamed to disk as frames come.
//  * the recording folder: every hostile OutputFilename refused by name or made unique, never an
//    existing file opened (the same names over the wire: rpIgtlCommandTest);
//  * the writer: the file on disk is a readable sequence after every batch, frames read back
//    exactly (shortest round-trip numbers), .igs.mha and .igs.nrrd; hostile tool names cannot
//    break the header;
//  * an hour of 10 tools at 60 Hz on a faked clock through the server's recorder: no allocation
//    after the first minute, heap and buffer flat (written to /dev/null: the bytes do not
//    matter, the memory does);
//  * a full disk (a tiny tmpfs in a private mount namespace): the recording stops with a message
//    naming the file and the reason, the file keeps every frame written before, readable; the
//    server's StopRecording says so.
#include <fcntl.h>
#include <malloc.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "rpAllocationCounter.h"
#include "rpAtomicFile.h"
#include "rpIgtlProtocol.h"
#include "rpIgtlServer.h"
#include "rpPlusRecorder.h"
#include "rpPlusSequenceFile.h"
#include "rpPlusSequenceWriter.h"
#include "rpRecordingFolder.h"
#include "rpTestOutput.h"
#include "rpTinyDisk.h"
#include "rpTrackingRecording.h"
#include "rpTrackingTestHelpers.h"

namespace fs = std::filesystem;
using namespace rp;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
extern "C" size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace {

std::string ReadText(const fs::path& path) {
  std::string text, error;
  return rp::ReadFile(path.string(), text, error) ? text : "(unreadable: " + error + ")";
}

// Heap bytes in use (the sanitizers' allocator when one runs, else glibc's).
size_t HeapBytes() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return __sanitizer_get_current_allocated_bytes();
#else
  return mallinfo2().uordblks;
#endif
}

// A pose that moves and turns with time: every number of the matrix has all its digits.
void MovingMatrix(int tool, double t, double m[16]) {
  const double a = 0.3 * t + tool, c = std::cos(a), s = std::sin(a);
  const double rows[16] = {c, -s, 0, 10.0 * tool + 5 * std::sin(t), s, c, 0, -40.25 + std::cos(1.3 * t), 0, 0, 1, -1500.5 + 0.1 * t,
                           0, 0, 0, 1};
  std::copy(rows, rows + 16, m);
}

const char* StateText(int frame, int tool) {
  return (frame + tool) % 17 == 0 ? "MISSING" : (frame + tool) % 23 == 0 ? "OUT_OF_VOLUME" : "OK";
}
ToolState StateOf(int frame, int tool) {
  return (frame + tool) % 17 == 0 ? ToolState::Missing : (frame + tool) % 23 == 0 ? ToolState::OutOfVolume : ToolState::OK;
}

// "<stem>_YYYYMMDD_HHMMSS<extension>", as PLUS names a recording beside an existing one.
bool DateAndTimeName(const std::string& name, const std::string& stem, const std::string& extension) {
  const std::string head = stem + "_";
  if (name.size() != head.size() + 15 + extension.size() || name.rfind(head, 0) != 0 ||
      name.compare(name.size() - extension.size(), extension.size(), extension) != 0)
    return false;
  for (size_t i = 0; i < 15; ++i) {
    const char c = name[head.size() + i];
    if (i == 8 ? c != '_' : !std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------- the recording folder

TEST(RecordingFolder, EveryHostileOutputFilenameIsRefusedByNameOrMadeUnique) {
  const fs::path dir = rptest::TestDir("folder");
  const fs::path outside = dir / "outside";
  const fs::path inside = dir / "recordings";
  fs::create_directories(outside);
  fs::create_directories(inside / "sub");
  { std::ofstream(outside / "victim.igs.mha") << "victim\n"; }
  { std::ofstream(inside / "existing.igs.mha") << "an earlier recording\n"; }
  fs::create_symlink(outside / "victim.igs.mha", inside / "link.igs.mha");
  fs::create_symlink(outside / "not-yet.igs.mha", inside / "dangling.igs.mha");
  RecordingFolder folder;
  std::string error;
  ASSERT_TRUE(folder.Open(inside.string(), error)) << error;

  struct Case {
    std::string Name, Why;
  };
  const std::vector<Case> refused = {
      {(outside / "victim.igs.mha").string(), "is an absolute path"},
      {(outside / "new.igs.mha").string(), "is an absolute path"},
      {"../outside/victim.igs.mha", "has a '..' part"},
      {"..", "has a '..' part"},
      {"sub/../../outside/victim.igs.mha", "has a '..' part"},
      {"sub/x.igs.mha", "names a folder"},
      {"link.igs.mha", "is a symbolic link in the recording folder"},
      {"dangling.igs.mha", "is a symbolic link in the recording folder"},
      {"", "is empty"},
      {"C:\\Users\\lab\\x.igs.mha", "is a Windows path"},
      {"..\\x.igs.mha", "is a Windows path"},
      {"x.txt", "is not a PLUS sequence file"},
      {".hidden.igs.mha", "is hidden"},
      {"a\nb.igs.mha", "control character"},
      {std::string(300, 'a') + ".igs.mha", "is longer than"},
  };
  for (const Case& c : refused) {
    RecordingFolder::Created created;
    EXPECT_FALSE(folder.Create(c.Name, created, error)) << c.Name;
    EXPECT_NE(error.find(c.Why), std::string::npos) << c.Name << ": " << error;
    EXPECT_EQ(created.Fd, -1);
  }
  EXPECT_FALSE(fs::exists(outside / "new.igs.mha"));
  EXPECT_FALSE(fs::exists(outside / "not-yet.igs.mha")) << "a dangling link was not followed";
  EXPECT_EQ(ReadText(outside / "victim.igs.mha"), "victim\n");

  // An existing name: a new file beside it, named as PLUS names recordings (date and time), never
  // the existing one; a second clash in the same second gets _2.
  const std::time_t when = 1800000000;  // a fixed time: 2027-01-15 (local time zone)
  RecordingFolder::Created first, second, plain;
  ASSERT_TRUE(folder.Create("existing.igs.mha", first, error, when)) << error;
  ASSERT_TRUE(folder.Create("existing.igs.mha", second, error, when)) << error;
  EXPECT_TRUE(first.MadeUnique && second.MadeUnique);
  EXPECT_TRUE(DateAndTimeName(first.Name, "existing", ".igs.mha")) << first.Name;
  EXPECT_EQ(second.Name, first.Name.substr(0, first.Name.size() - 8) + "_2.igs.mha");
  EXPECT_EQ(first.Path, (inside / first.Name).string());
  ASSERT_TRUE(folder.Create("new.IGS.NRRD", plain, error)) << error;
  EXPECT_FALSE(plain.MadeUnique);
  for (int fd : {first.Fd, second.Fd, plain.Fd}) ::close(fd);
  EXPECT_EQ(ReadText(inside / "existing.igs.mha"), "an earlier recording\n");
  EXPECT_EQ(fs::file_size(inside / first.Name), 0u);
}

// ---------------------------------------------------------------- the streaming writer

TEST(PlusSequenceWriter, FramesReachTheDiskAsTheyComeAndTheFileReadsAfterEveryBatch) {
  const fs::path dir = rptest::TestDir("stream");
  for (const char* name : {"stream.igs.mha", "stream.igs.nrrd"}) {
    SCOPED_TRACE(name);
    const fs::path path = dir / name;
    PlusSequenceWriter writer;
    std::string error;
    ASSERT_TRUE(writer.Create(path.string(), error)) << error;
    EXPECT_EQ(ReadPlusSequence(path.string()).Frames.size(), 0u) << "a new recording reads (no frames)";
    const char* tools[3] = {"StylusToTracker", "ReferenceToTracker", "ProbeToTracker"};
    uint64_t lastWritten = 0;
    int checks = 0;
    const int frames = 5 * 60;  // 5 s at 60 Hz on a faked clock: a batch each second
    for (int f = 0; f < frames; ++f) {
      const double t = 1000.0 + f / 60.0;
      writer.BeginFrame(t);
      for (int k = 0; k < 3; ++k) {
        double m[16];
        MovingMatrix(k, t, m);
        writer.AddTransform(tools[k], m, StateOf(f, k));
      }
      ASSERT_TRUE(writer.EndFrame());
      if (writer.FramesWritten() != lastWritten) {  // a batch went to disk: the file reads, every frame so far
        lastWritten = writer.FramesWritten();
        const PlusSequence s = ReadPlusSequence(path.string());
        ASSERT_EQ(s.Frames.size(), lastWritten);
        EXPECT_EQ(s.Frames.back().Timestamp, 1000.0 + static_cast<double>(lastWritten - 1) / 60.0);
        ++checks;
      }
    }
    EXPECT_GE(checks, 4);
    ASSERT_TRUE(writer.Close(&error)) << error;
    const PlusSequence s = ReadPlusSequence(path.string());
    ASSERT_EQ(s.Frames.size(), static_cast<size_t>(frames));
    ASSERT_EQ(s.TransformNames, (std::vector<std::string>{"StylusToTracker", "ReferenceToTracker", "ProbeToTracker"}));
    for (int f = 0; f < frames; ++f) {
      const double t = 1000.0 + f / 60.0;
      ASSERT_EQ(s.Frames[f].Timestamp, t);
      for (int k = 0; k < 3; ++k) {
        double m[16];
        MovingMatrix(k, t, m);
        const PlusSequence::Transform& tr = s.Frames[f].Transforms[k];
        ASSERT_TRUE(tr.Present);
        for (int i = 0; i < 16; ++i) ASSERT_EQ(tr.Matrix[i], m[i]) << "exact: shortest round-trip text";
        ASSERT_STREQ(PlusToolStatusName(tr.State), StateText(f, k));
      }
    }
    // PLUS's layout: the count in the header, padded to PLUS's 40 characters.
    const std::string text = ReadText(path);
    EXPECT_NE(text.find(std::string(name).find("nrrd") != std::string::npos ? "\nsizes: 0 0 300" : "\nDimSize = 0 0 300"),
              std::string::npos);
  }
}

TEST(PlusSequenceWriter, ToolNamesAndValuesCannotBreakTheHeader) {
  const fs::path path = rptest::TestDir("names") / "names.igs.mha";
  PlusSequenceWriter writer;
  std::string error;
  ASSERT_TRUE(writer.Create(path.string(), error)) << error;
  const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const double broken[16] = {NAN, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, INFINITY, 0, 0, 0, 1};
  writer.BeginFrame(1.5);
  writer.AddTransform("Evil\nElementDataFile = LOCAL\nToTracker", identity, ToolState::OK);
  writer.AddTransform("BrokenToTracker", broken, ToolState::OK);
  writer.AddField("Note", "a\nb = c");
  ASSERT_TRUE(writer.EndFrame());
  ASSERT_TRUE(writer.Close(&error)) << error;
  const PlusSequence s = ReadPlusSequence(path.string());
  ASSERT_EQ(s.Frames.size(), 1u);
  ASSERT_EQ(s.TransformNames.size(), 2u);
  EXPECT_EQ(s.TransformNames[0], "Evil_ElementDataFile___LOCAL_ToTracker");
  EXPECT_EQ(s.Frames[0].Transforms[1].State, ToolState::Missing) << "a non-finite pose is written INVALID";
  EXPECT_EQ(s.Frames[0].Fields.at(0).second, "a_b _ c");
}

TEST(PlusSequenceWriter, TrackRecordStreamsAPlusRecordingThatReadsBack) {
  const fs::path path = rptest::TestDir("track-record") / "track.igs.mha";
  RecordingWriter recorder;
  std::string error;
  ASSERT_TRUE(recorder.Open(path.string(), error)) << error;
  for (int f = 0; f < 100; ++f)
    for (const char* tool : {"Stylus", "Reference"}) {
      ToolPose p;
      p.Translation[0] = f;
      p.State = ToolState::OK;
      recorder.Add(tool, f * 0.02, p);
    }
  ASSERT_TRUE(recorder.Close(&error)) << error;
  const Recording r = Recording::Read(path.string());
  EXPECT_EQ(r.Tools, (std::vector<std::string>{"StylusToTracker", "ReferenceToTracker"}));
  ASSERT_EQ(r.Samples.size(), 200u);
  EXPECT_EQ(r.Samples.back().Pose.Translation[0], 99.0);
  EXPECT_EQ(ReadPlusSequence(path.string()).Frames.size(), 100u);  // one frame per time stamp
}

// An hour of 10 tools at 60 Hz through the server's recorder, on a faked clock: 216 000 frames.
TEST(PlusRecorder, AnHourOfTenToolsAt60HzKeepsMemoryFlat) {
  ToolPoseTable table;
  ToolPoseReader reader;
  int slots[10];
  for (int k = 0; k < 10; ++k) slots[k] = table.FindOrAdd(("Tool" + std::to_string(k) + "ToTracker").c_str());
  PlusRecorder recorder;
  std::string message;
  const int sink = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  ASSERT_GE(sink, 0);
  ASSERT_TRUE(recorder.Start(sink, "hour.igs.mha", message)) << message;
  const int perMinute = 60 * 60, minutes = 60;
  size_t heapAfterFirstMinute = 0, bufferAfterFirstMinute = 0;
  uint64_t allocationsAfterFirstMinute = 0;
  for (int minute = 0; minute < minutes; ++minute) {
    for (int i = 0; i < perMinute; ++i) {
      const int frame = minute * perMinute + i;
      const double t = frame / 60.0;
      for (int k = 0; k < 10; ++k) {
        double m[16];
        MovingMatrix(k, t, m);
        ToolPose pose;
        pose.FromMatrix(m);
        pose.State = StateOf(frame, k);
        table.Publish(slots[k], pose);
        reader.Poll(table, slots[k]);
      }
      ASSERT_TRUE(recorder.Record(t, table, reader));
    }
    if (minute == 0) {
      heapAfterFirstMinute = HeapBytes();
      bufferAfterFirstMinute = recorder.CurrentWriter()->BufferCapacity();
      allocationsAfterFirstMinute = alloc::ThreadAllocations();
    }
  }
  const uint64_t allocations = alloc::ThreadAllocations() - allocationsAfterFirstMinute;
  const PlusSequenceWriter& writer = *recorder.CurrentWriter();
  EXPECT_EQ(writer.Frames(), static_cast<uint64_t>(perMinute * minutes));
  EXPECT_EQ(allocations, 0u) << "the recorder allocated after its first minute";
  EXPECT_EQ(writer.BufferCapacity(), bufferAfterFirstMinute);
  EXPECT_LE(writer.BufferCapacity(), 80u << 10);
  const size_t heapAtTheEnd = HeapBytes();
  EXPECT_LE(heapAtTheEnd, heapAfterFirstMinute + (64u << 10)) << "heap after minute 1: " << heapAfterFirstMinute << ", after 60: " << heapAtTheEnd;
  ASSERT_TRUE(recorder.Stop(message)) << message;
  EXPECT_EQ(message, "Recording 216000 frames successful to file hour.igs.mha");
  std::printf("[hour] 216000 frames of 10 tools: heap %zu bytes after minute 1, %zu after minute 60; batch buffer %zu bytes; "
              "%llu allocations after minute 1 (the in-memory recording it replaces kept ~%.0f MB)\n",
              heapAfterFirstMinute, heapAtTheEnd, bufferAfterFirstMinute, static_cast<unsigned long long>(allocations),
              216000.0 * 10 * (sizeof(PlusSequence::Transform)) / 1e6);
}

// ---------------------------------------------------------------- a full disk

namespace {

// A raw client's COMMAND: its RTS_COMMAND's Status + ": " + Message.
std::string Command(test::IgtlTestClient& client, const std::string& xml) {
  std::string status, message;
  return client.Command(xml, status, message) ? status + ": " + message : "no reply";
}

// The child's work on the tiny disk: the writer alone, then the server's StartRecording and
// StopRecording from a client. One line per finding, for the parent.
std::string FullDiskRun(const fs::path& dir) {
  std::ostringstream report;
  // 1. The writer until the disk refuses a batch.
  {
    PlusSequenceWriter writer;
    std::string error;
    if (!writer.Create((dir / "writer.igs.mha").string(), error)) return "fail\n" + error;
    double m[16];
    int f = 0;
    for (; f < 1000000; ++f) {
      writer.BeginFrame(f / 60.0);
      for (int k = 0; k < 10; ++k) {
        MovingMatrix(k, f / 60.0, m);
        writer.AddTransform(("Tool" + std::to_string(k) + "ToTracker").c_str(), m, ToolState::OK);
      }
      if (!writer.EndFrame()) break;
    }
    const uint64_t written = writer.FramesWritten();
    report << "writer-stopped " << (f < 1000000) << "\nwriter-error " << writer.Error() << "\n";
    writer.Close();
    try {
      const PlusSequence s = ReadPlusSequence((dir / "writer.igs.mha").string());
      double expected[16];
      MovingMatrix(9, static_cast<double>(written - 1) / 60.0, expected);
      const bool last = !s.Frames.empty() && std::equal(expected, expected + 16, s.Frames.back().Transforms.at(9).Matrix);
      report << "writer-frames " << written << " " << s.Frames.size() << " " << last << "\n";
    } catch (const std::exception& e) {
      report << "writer-unreadable " << e.what() << "\n";
    }
    fs::remove(dir / "writer.igs.mha");
  }
  // 2. The server recording for a client until the disk is full.
  ToolPoseTable table;
  int slots[16];
  for (int k = 0; k < 16; ++k) slots[k] = table.FindOrAdd(("Tool" + std::to_string(k) + "ToTracker").c_str());
  std::mutex mutex;
  std::vector<std::string> log;
  IgtlServer::Options o;
  o.Port = 0;
  o.SendHz = 400;
  o.RecordFolder = dir.string();
  o.Log = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex);
    log.push_back(line);
  };
  IgtlServer server(table, o);
  std::string error;
  if (!server.Start(error)) return "fail\n" + error;
  std::atomic<bool> run{true};
  std::thread tracker([&] {
    for (int f = 0; run; ++f) {
      for (int k = 0; k < 16; ++k) {
        double m[16];
        MovingMatrix(k, f / 400.0, m);
        ToolPose p;
        p.FromMatrix(m);
        p.State = ToolState::OK;
        table.Publish(slots[k], p);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(1500));
    }
  });
  test::IgtlTestClient client(server.Port());
  if (!client.Connected()) return "fail\nconnect";
  // PlusServer's CLIENTINFO without TRANSFORM: this client gets keep-alives only, so it can sit
  // without reading while the disk fills (a client that reads nothing for 2 s is dropped).
  const std::string info = "<ClientInfo><MessageTypes><Message Type=\"STATUS\" /></MessageTypes></ClientInfo>";
  std::vector<uint8_t> content(igtl::StringHeaderSize + info.size());
  igtl::EncodeString(info.data(), info.size(), content.data());
  const auto clientInfo = igtl::BuildMessage(1, "CLIENTINFO", "Client", WallSeconds(), content.data(), content.size());
  if (!client.Send(clientInfo)) return "fail\nclientinfo";
  report << "start " << Command(client, "<Command Name=\"StartRecording\" OutputFilename=\"server.igs.mha\" />") << "\n";
  bool stopped = false;
  for (int i = 0; i < 600 && !stopped; ++i) {  // up to 30 s
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& line : log) stopped |= line.rfind("recording stopped: ", 0) == 0;
  }
  report << "logged-stop " << stopped << "\n";
  report << "stop " << Command(client, "<Command Name=\"StopRecording\" />") << "\n";
  run = false;
  tracker.join();
  server.Stop();
  try {
    report << "server-frames " << ReadPlusSequence((dir / "server.igs.mha").string()).Frames.size() << "\n";
  } catch (const std::exception& e) {
    report << "server-unreadable " << e.what() << "\n";
  }
  return "ran\n" + report.str();
}

}  // namespace

TEST(PlusRecorder, AFullDiskStopsTheRecordingWithAClearReplyAndKeepsWhatWasWrittenReadable) {
  const fs::path dir = rptest::TestDir("full-disk");
  const std::string result = rptest::RunOnTinyDisk(dir, 256, [&] { return FullDiskRun(dir); });
  if (result.rfind("skip\n", 0) == 0)
    GTEST_SKIP() << "cannot mount a tiny tmpfs here (needs root, CAP_SYS_ADMIN or user namespaces): " << result.substr(5);
  ASSERT_EQ(result.rfind("ran\n", 0), 0u) << result;
  std::printf("[full disk]\n%s", result.c_str());
  std::map<std::string, std::string> found;
  std::istringstream lines(result);
  for (std::string line; std::getline(lines, line);) {
    const size_t space = line.find(' ');
    if (space != std::string::npos) found[line.substr(0, space)] = line.substr(space + 1);
  }
  EXPECT_EQ(found["writer-stopped"], "1");
  EXPECT_NE(found["writer-error"].find("No space left on device"), std::string::npos) << result;
  EXPECT_NE(found["writer-error"].find("writer.igs.mha after "), std::string::npos) << result;
  // "<frames written> <frames read back> <the last frame read back exactly>"
  std::istringstream frames(found["writer-frames"]);
  uint64_t written = 0, read = 0;
  int last = 0;
  frames >> written >> read >> last;
  EXPECT_GT(written, 10u) << result;
  EXPECT_EQ(read, written) << result;
  EXPECT_EQ(last, 1) << result;
  EXPECT_EQ(found["start"].rfind("SUCCESS: Recording to ", 0), 0u) << result;
  EXPECT_EQ(found["logged-stop"], "1") << result;
  EXPECT_EQ(found["stop"].rfind("FAIL: Recording stopped early: cannot write ", 0), 0u) << result;
  EXPECT_NE(found["stop"].find("No space left on device"), std::string::npos) << result;
  EXPECT_NE(found["stop"].find("frames written are kept (a readable sequence)"), std::string::npos) << result;
  EXPECT_GT(std::atoi(found["server-frames"].c_str()), 10) << result;
}
