// Tracking benchmarks. The peer and "the library way" are upstream OpenIGTLink 3.x (PLUS's and
// Slicer's library) when the oracle is built, else Debian's OpenIGTLink (ROBOPLAN_IGTL_LIBRARY_NAME).
//  * Parsers (Google Benchmark): NDI BX/TX replies; an OpenIGTLink TRANSFORM decoded by our
//    non-allocating parser vs the library's Unpack (what Slicer's connector does).
//  * Sender to scene, 10 tools at 60 Hz (a tracker through PLUS): from the sender's time stamp
//    to the tool node's ModifiedEvent in the scene. Ours with the main thread woken by the
//    source's data, and ours polled by a 60 Hz display timer; against the way Slicer's
//    OpenIGTLinkIF (OpenIGTLinkIO) does it on the library: a receive thread putting each
//    message into a mutex-guarded buffer per device, a 5 ms main-thread timer unpacking it
//    (with CRC) into the node.
//  * Ingestion on loopback, 10 tools: throughput (flood) and sender-to-buffer latency at 20,000
//    TRANSFORM/s (paced), for our client and for the library's own receive loop (ClientSocket +
//    MessageHeader + Unpack with CRC) in the same run.
//  * Serial polling at 60 Hz against the simulator: CPU of the driver thread, BX vs TX.
// Figures (JSON, CSV) and charts (PNG; without a display on a private Xvfb, rpXDisplay.h) go to
// $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output. A quick run (ROBOPLAN_BENCHMARK_QUICK) floods
// and paces for 0.2 s, follows the scene for 0.7 s a way and polls the serial port for 0.3 s.
#include <benchmark/benchmark.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>

#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlServerSocket.h>
#include <igtlTransformMessage.h>
#include <nlohmann/json.hpp>
#include <poll.h>
#include <vtkCallbackCommand.h>
#include <vtkNew.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpIgtlClient.h"
#include "rpIgtlProtocol.h"
#include "rpNdiProtocol.h"
#include "rpNdiTracker.h"
#include "rpPolarisSimulator.h"
#include "rpToolDefinition.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"
#include "rpTrackingTestHelpers.h"

using namespace rp;

namespace {

constexpr int kTools = 10;

// Socket::Receive of the library in use: 3.x takes a timeout flag, Debian's 1.11 does not.
template <class S, class N>
auto ReceiveImpl(S& socket, void* data, N size, int) -> decltype(socket->Receive(data, size)) {
  return socket->Receive(data, size);
}
template <class S, class N>
auto ReceiveImpl(S& socket, void* data, N size, long) -> decltype(socket->Receive(data, size, std::declval<bool&>())) {
  bool timeout = false;
  return socket->Receive(data, size, timeout);
}
template <class S, class N>
auto ReceiveAll(S& socket, void* data, N size) {
  return ReceiveImpl(socket, data, size, 0);
}

std::vector<uint8_t> BxReply(int tools) {
  std::vector<uint8_t> body = {static_cast<uint8_t>(tools)};
  auto put = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) body.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  for (int t = 0; t < tools; ++t) {
    body.push_back(static_cast<uint8_t>(0x0A + t));
    body.push_back(0x01);
    for (float f : {1.f, 0.f, 0.f, 0.f, 10.f, 20.f, -1500.f, 0.1f}) {
      uint32_t bits;
      std::memcpy(&bits, &f, 4);
      put(bits);
    }
    put(0x31);
    put(1234);
  }
  body.push_back(0);
  body.push_back(0);
  std::vector<uint8_t> f = {0xC4, 0xA5, static_cast<uint8_t>(body.size()), static_cast<uint8_t>(body.size() >> 8)};
  const uint16_t h = ndi::Crc16(f.data(), 4);
  f.push_back(static_cast<uint8_t>(h));
  f.push_back(static_cast<uint8_t>(h >> 8));
  f.insert(f.end(), body.begin(), body.end());
  const uint16_t c = ndi::Crc16(body.data(), body.size());
  f.push_back(static_cast<uint8_t>(c));
  f.push_back(static_cast<uint8_t>(c >> 8));
  return f;
}

std::string TxReply(int tools) {
  std::string p;
  char b[16];
  std::snprintf(b, sizeof b, "%02X", tools);
  p += b;
  for (int t = 0; t < tools; ++t) {
    std::snprintf(b, sizeof b, "%02X", 0x0A + t);
    p += b;
    p += "+10000+00000+00000+00000+001000-002050-150025+01234000000310000001A\n";
  }
  p += "0000";
  char crc[4];
  ndi::WriteHex(crc, ndi::Crc16(p.data(), p.size()), 4);
  return p + std::string(crc, 4) + "\r";
}

void BM_NdiParseBx(benchmark::State& state) {
  const auto frame = BxReply(static_cast<int>(state.range(0)));
  ndi::TrackingReply reply;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ndi::ParseBx(frame.data(), frame.size(), reply));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_NdiParseBx)->Arg(3)->Arg(10);

void BM_NdiParseTx(benchmark::State& state) {
  const auto frame = TxReply(static_cast<int>(state.range(0)));
  ndi::TrackingReply reply;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ndi::ParseTx(reinterpret_cast<const uint8_t*>(frame.data()), frame.size(), reply));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_NdiParseTx)->Arg(3)->Arg(10);

std::vector<uint8_t> LibraryTransform(const char* name, double timestamp) {
  auto msg = ::igtl::TransformMessage::New();
  msg->SetDeviceName(name);
  ::igtl::Matrix4x4 m;
  ::igtl::IdentityMatrix(m);
  m[0][3] = 12.5f;
  m[2][3] = -1500.f;
  msg->SetMatrix(m);
  const double whole = std::floor(timestamp);
  msg->SetTimeStamp(static_cast<unsigned int>(whole), static_cast<unsigned int>((timestamp - whole) * 4294967296.0));
  msg->Pack();
  const uint8_t* p = static_cast<const uint8_t*>(msg->GetPackPointer());
  return std::vector<uint8_t>(p, p + msg->GetPackSize());
}

void BM_IgtlTransformOurs(benchmark::State& state) {
  const auto bytes = LibraryTransform("StylusToTracker", 1.0);
  for (auto _ : state) {
    rp::igtl::Header h;
    rp::igtl::ParseHeader(bytes.data(), h, 1 << 20);
    const bool crcOk = rp::igtl::Crc64(bytes.data() + 58, h.BodySize) == h.Crc;
    double m[16];
    rp::igtl::DecodeTransform(bytes.data() + 58, h.BodySize, m);
    ToolPose p;
    p.FromMatrix(m);
    benchmark::DoNotOptimize(crcOk);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_IgtlTransformOurs);

void BM_IgtlTransformLibrary(benchmark::State& state) {
  const auto bytes = LibraryTransform("StylusToTracker", 1.0);
  for (auto _ : state) {
    auto header = ::igtl::MessageHeader::New();
    header->InitPack();
    std::memcpy(header->GetPackPointer(), bytes.data(), 58);
    header->Unpack();
    auto msg = ::igtl::TransformMessage::New();
    msg->SetMessageHeader(header);
    msg->AllocatePack();
    std::memcpy(msg->GetPackBodyPointer(), bytes.data() + 58, 48);
    msg->Unpack(1);
    ::igtl::Matrix4x4 m;
    msg->GetMatrix(m);
    benchmark::DoNotOptimize(m);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_IgtlTransformLibrary);

// ---------------------------------------------------------------- loopback ingestion


// The sender: a peer built with the OpenIGTLink library. Flood (pre-packed batches of one
// message per tool) then paced at `rate` messages/s with fresh timestamps.
struct Sender {
  std::atomic<int> Phase{0};  // 0 wait, 1 flood, 2 paced, 3 done
  std::atomic<uint64_t> Sent{0};
  double Rate = 20000;
  double FloodSeconds = rp::bench::QuickRun() ? 0.2 : 2, PacedSeconds = FloodSeconds;
  int Port = test::FreePort();
  std::thread Thread;
  ::igtl::ServerSocket::Pointer Server = ::igtl::ServerSocket::New();

  void Start() {
    Server->CreateServer(Port);
    Thread = std::thread([this] {
      ::igtl::ClientSocket::Pointer s;
      for (int i = 0; i < 100 && !(s = Server->WaitForConnection(50)); ++i) {
      }
      if (!s) return;
      char names[kTools][20];
      for (int t = 0; t < kTools; ++t) std::snprintf(names[t], sizeof names[t], "Tool%dToTracker", t);
      while (Phase == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      std::vector<uint8_t> batch;
      for (int t = 0; t < kTools; ++t) {
        const auto m = LibraryTransform(names[t], WallSeconds());
        batch.insert(batch.end(), m.begin(), m.end());
      }
      const double floodEnd = SteadySeconds() + FloodSeconds;
      while (SteadySeconds() < floodEnd) {
        if (!s->Send(batch.data(), static_cast<int>(batch.size()))) return;
        Sent += kTools;
      }
      Phase = 2;
      std::this_thread::sleep_for(std::chrono::milliseconds(300));  // drain
      const double period = kTools / Rate;
      double next = SteadySeconds();
      const double pacedEnd = next + PacedSeconds;
      while (next < pacedEnd) {
        const double wait = next - SteadySeconds();  // sleep, not spin: the receiver needs the core
        if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
        batch.clear();
        for (int t = 0; t < kTools; ++t) {
          const auto m = LibraryTransform(names[t], WallSeconds());
          batch.insert(batch.end(), m.begin(), m.end());
        }
        if (!s->Send(batch.data(), static_cast<int>(batch.size()))) return;
        Sent += kTools;
        next += period;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      Phase = 3;
      s->CloseSocket();
    });
  }
  ~Sender() {
    if (Thread.joinable()) Thread.join();
    Server->CloseSocket();
  }
};

struct IngestionResult {
  std::string Receiver;
  double ThroughputPerSecond = 0;
  double P50 = 0, P99 = 0, P999 = 0, Max = 0;
  double SocketP50 = -1, SocketP99 = -1, SocketP999 = -1;  // kernel receive -> buffer (ours only)
  uint64_t Received = 0, Sent = 0, CrcErrors = 0, DisplayDropped = 0;
  std::vector<uint64_t> Histogram, SocketHistogram;
};

// Waits until `count()` reaches `target` (or 5 s); returns the time it took from `start`.
double Drain(const std::function<uint64_t()>& count, uint64_t target, double start) {
  const double deadline = SteadySeconds() + 5;
  while (count() < target && SteadySeconds() < deadline) std::this_thread::sleep_for(std::chrono::microseconds(200));
  return SteadySeconds() - start;
}

IngestionResult RunOurClient() {
  Sender sender;
  sender.Start();
  IgtlClient::Options o;
  o.Port = sender.Port;
  IgtlClient client(o);
  client.Start();
  while (!client.Connected()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  IngestionResult r;
  r.Receiver = "RoboPlan IgtlClient";
  auto count = [&] { return client.GetStatistics().Poses; };
  // A "display" reading at 60 Hz, as the main thread would: keeps the newest pose per tool.
  std::atomic<bool> displayStop{false};
  ToolPoseReader reader;
  std::thread display([&] {
    while (!displayStop) {
      for (int i = 0; i < client.Poses().Count(); ++i) reader.Poll(client.Poses(), i);
      std::this_thread::sleep_for(std::chrono::milliseconds(16));
    }
  });
  const double start = SteadySeconds();
  sender.Phase = 1;
  while (sender.Phase == 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const uint64_t flooded = sender.Sent;
  const double seconds = Drain(count, flooded, start);
  r.ThroughputPerSecond = static_cast<double>(count()) / seconds;
  client.EnableLatency(true);
  while (sender.Phase != 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  client.EnableLatency(false);
  displayStop = true;
  display.join();
  r.Sent = sender.Sent;
  r.Received = count();
  r.CrcErrors = client.GetStatistics().CrcErrors;
  for (int i = 0; i < client.Poses().Count(); ++i) r.DisplayDropped += reader.Last(i).Dropped;
  r.Histogram = client.LatencyHistogram();
  r.SocketHistogram = client.SocketLatencyHistogram();
  client.Stop();
  return r;
}

IngestionResult RunLibraryLoop() {
  Sender sender;
  sender.Start();
  auto socket = ::igtl::ClientSocket::New();
  while (socket->ConnectToServer("127.0.0.1", sender.Port) != 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  IngestionResult r;
  r.Receiver = std::string(ROBOPLAN_IGTL_LIBRARY_NAME) + " receive loop";
  std::atomic<uint64_t> received{0}, crcErrors{0};
  std::atomic<bool> measure{false};
  std::vector<uint64_t> histogram(IgtlClient::LatencyBins, 0);
  std::thread loop([&] {
    auto header = ::igtl::MessageHeader::New();
    auto msg = ::igtl::TransformMessage::New();
    for (;;) {
      header->InitPack();
      if (ReceiveAll(socket, header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return;
      header->Unpack();
      msg->SetMessageHeader(header);
      msg->AllocatePack();
      if (ReceiveAll(socket, msg->GetPackBodyPointer(), msg->GetPackBodySize()) != msg->GetPackBodySize()) return;
      if (!(msg->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY)) {
        ++crcErrors;
        continue;
      }
      ::igtl::Matrix4x4 m;
      msg->GetMatrix(m);
      benchmark::DoNotOptimize(m);
      if (measure) {
        unsigned int sec = 0, frac = 0;
        header->GetTimeStamp(&sec, &frac);
        const double latency = WallSeconds() - (sec + frac / 4294967296.0);
        long bin = static_cast<long>(latency * 1e6);
        bin = std::max(0L, std::min<long>(bin, IgtlClient::LatencyBins - 1));
        ++histogram[static_cast<size_t>(bin)];
      }
      ++received;
    }
  });
  const double start = SteadySeconds();
  sender.Phase = 1;
  while (sender.Phase == 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const double seconds = Drain([&] { return received.load(); }, sender.Sent, start);
  r.ThroughputPerSecond = static_cast<double>(received) / seconds;
  measure = true;
  while (sender.Phase != 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  loop.join();  // the sender closed: Receive fails and the loop ends
  r.Sent = sender.Sent;
  r.Received = received;
  r.CrcErrors = crcErrors;
  r.Histogram = histogram;
  return r;
}

void Summarise(IngestionResult& r) {
  r.P50 = IgtlClient::HistogramPercentile(r.Histogram, 0.50);
  r.P99 = IgtlClient::HistogramPercentile(r.Histogram, 0.99);
  r.P999 = IgtlClient::HistogramPercentile(r.Histogram, 0.999);
  r.Max = IgtlClient::HistogramPercentile(r.Histogram, 1.0);
  if (!r.SocketHistogram.empty()) {
    r.SocketP50 = IgtlClient::HistogramPercentile(r.SocketHistogram, 0.50);
    r.SocketP99 = IgtlClient::HistogramPercentile(r.SocketHistogram, 0.99);
    r.SocketP999 = IgtlClient::HistogramPercentile(r.SocketHistogram, 0.999);
  }
}

// ---------------------------------------------------------------- sender to scene

struct SceneLatency {
  std::string Mode;
  std::vector<uint64_t> Histogram = std::vector<uint64_t>(IgtlClient::LatencyBins, 0);  // 1 µs bins
  uint64_t Sent = 0, Updates = 0;
  double P50 = 0, P99 = 0, P999 = 0, Max = 0;
};

enum class SceneMode {
  WokenByData,   // RoboPlan: the main thread sleeps on the source's ready fd
  Timer60Hz,     // RoboPlan's client, polled by a 60 Hz display timer
  LibraryTimer,  // the library as Slicer's OpenIGTLinkIF uses it (receive thread, locked buffer, 5 ms timer)
};

const char* SceneModeName(SceneMode mode) {
  switch (mode) {
    case SceneMode::WokenByData: return "RoboPlan: woken by the data";
    case SceneMode::Timer60Hz: return "RoboPlan: 60 Hz display timer";
    case SceneMode::LibraryTimer: return "OpenIGTLinkIF way: library thread + 5 ms timer";
  }
  return "";
}

// Slicer's OpenIGTLinkIF on the library (OpenIGTLinkIO's connector): a receive thread reads each
// message (header, then body) into a mutex-guarded buffer per device name; the main thread's
// 5 ms timer (qIGTLIOLogicController) takes the newest of each device, unpacks it with CRC and
// writes the transform node.
class LibraryConnector {
public:
  explicit LibraryConnector(int port) : Port(port) {
    this->Thread = std::thread([this] { this->Receive(); });
  }
  ~LibraryConnector() {  // after the sender closed: the receive thread has seen the end of the stream
    this->Stop = true;
    if (this->Thread.joinable()) this->Thread.join();
    this->Socket->CloseSocket();
  }
  // Main thread, every 5 ms: one node write per device that received a message since last time.
  void Import(vtkRPScene* scene) {
    std::map<std::string, std::vector<uint8_t>> taken;
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      taken.swap(this->Pending);
    }
    if (taken.empty()) return;
    scene->StartBatchProcess();
    for (auto& [name, bytes] : taken) {
      auto header = ::igtl::MessageHeader::New();
      header->InitPack();
      std::memcpy(header->GetPackPointer(), bytes.data(), static_cast<size_t>(header->GetPackSize()));
      header->Unpack();
      auto msg = ::igtl::TransformMessage::New();
      msg->SetMessageHeader(header);
      msg->AllocatePack();
      std::memcpy(msg->GetPackBodyPointer(), bytes.data() + header->GetPackSize(), static_cast<size_t>(msg->GetPackBodySize()));
      if (!(msg->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY)) continue;
      ::igtl::Matrix4x4 m;
      msg->GetMatrix(m);
      unsigned int sec = 0, frac = 0;
      header->GetTimeStamp(&sec, &frac);
      vtkRPTrackedToolNode* node = nullptr;
      for (vtkRPNode* candidate : scene->GetNodesByName(name))
        if ((node = vtkRPTrackedToolNode::SafeDownCast(candidate))) break;
      if (!node) {
        vtkNew<vtkRPTrackedToolNode> created;
        created->SetName(name.c_str());
        scene->AddNode(created);
        node = created;
      }
      double matrix[16];
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) matrix[4 * i + j] = m[i][j];
      const int wasModifying = node->StartModify();
      node->SetMatrixTransformToParent(matrix);
      node->SetStatus(vtkRPTrackedToolNode::StatusOK);
      node->SetTimestamp(sec + frac / 4294967296.0);
      node->EndModify(wasModifying);
    }
    scene->EndBatchProcess();
  }

private:
  void Receive() {
    while (!this->Stop && this->Socket->ConnectToServer("127.0.0.1", this->Port) != 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    auto header = ::igtl::MessageHeader::New();
    std::vector<uint8_t> message;
    while (!this->Stop) {
      header->InitPack();
      const auto headerSize = header->GetPackSize();
      message.resize(static_cast<size_t>(headerSize));  // the wire bytes (Unpack swaps the header in place)
      if (static_cast<size_t>(ReceiveAll(this->Socket, message.data(), headerSize)) != static_cast<size_t>(headerSize)) return;
      std::memcpy(header->GetPackPointer(), message.data(), static_cast<size_t>(headerSize));
      header->Unpack();
      const auto bodySize = header->GetBodySizeToRead();
      message.resize(static_cast<size_t>(headerSize) + static_cast<size_t>(bodySize));
      if (bodySize && static_cast<size_t>(ReceiveAll(this->Socket, message.data() + headerSize, bodySize)) != static_cast<size_t>(bodySize))
        return;
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Pending[header->GetDeviceName()] = message;
    }
  }

  int Port;
  std::atomic<bool> Stop{false};
  ::igtl::ClientSocket::Pointer Socket = ::igtl::ClientSocket::New();
  std::mutex Mutex;
  std::map<std::string, std::vector<uint8_t>> Pending;  // newest message per device
  std::thread Thread;
};

// A tracker behind PLUS: 10 tools, one TRANSFORM each per frame at 60 Hz, time stamped when sent.
SceneLatency RunSenderToScene(SceneMode mode, double seconds) {
  SceneLatency r;
  r.Mode = SceneModeName(mode);
  const bool wakeOnData = mode == SceneMode::WokenByData;
  const int port = test::FreePort();
  auto server = ::igtl::ServerSocket::New();
  server->CreateServer(port);
  std::atomic<bool> done{false};
  std::atomic<uint64_t> sent{0};
  std::thread sender([&] {
    ::igtl::ClientSocket::Pointer s;
    for (int i = 0; i < 100 && !(s = server->WaitForConnection(50)); ++i) {
    }
    if (!s) return;
    char names[kTools][20];
    for (int t = 0; t < kTools; ++t) std::snprintf(names[t], sizeof names[t], "Tool%dToTracker", t);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the client settles
    const double period = 1.0 / 60.0;
    double next = SteadySeconds();
    const double end = next + seconds;
    std::vector<uint8_t> batch;
    while (next < end) {
      const double wait = next - SteadySeconds();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
      batch.clear();
      for (int t = 0; t < kTools; ++t) {
        const auto m = LibraryTransform(names[t], WallSeconds());
        batch.insert(batch.end(), m.begin(), m.end());
      }
      if (!s->Send(batch.data(), static_cast<int>(batch.size()))) break;
      sent += kTools;
      next += period;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    done = true;
    s->CloseSocket();
  });
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  logic->SetStaleTimeout(10);
  IgtlClient::Options o;
  o.Port = port;
  o.ReconnectInitialSeconds = 0.01;
  std::string error;
  std::unique_ptr<LibraryConnector> library;
  if (mode == SceneMode::LibraryTimer)
    library = std::make_unique<LibraryConnector>(port);
  else
    logic->AddSource(std::make_unique<IgtlClient>(o), error);
  // Every tool node's ModifiedEvent: now − the sender's time stamp of the pose it shows.
  struct Sink {
    SceneLatency* Result;
    bool Measure = false;
  } sink{&r};
  vtkNew<vtkCallbackCommand> onModified;
  onModified->SetClientData(&sink);
  onModified->SetCallback([](vtkObject* caller, unsigned long, void* data, void*) {
    auto* s = static_cast<Sink*>(data);
    auto* node = vtkRPTrackedToolNode::SafeDownCast(caller);
    if (!s->Measure || !node) return;
    const long bin = static_cast<long>((WallSeconds() - node->GetTimestamp()) * 1e6);
    ++s->Result->Histogram[static_cast<size_t>(std::max(0L, std::min<long>(bin, IgtlClient::LatencyBins - 1)))];
    ++s->Result->Updates;
  });
  vtkNew<vtkCallbackCommand> onAdded;
  onAdded->SetClientData(onModified.Get());
  onAdded->SetCallback([](vtkObject*, unsigned long, void* observer, void* node) {
    if (auto* tool = vtkRPTrackedToolNode::SafeDownCast(static_cast<vtkObject*>(node)))
      tool->AddObserver(vtkCommand::ModifiedEvent, static_cast<vtkCallbackCommand*>(observer));
  });
  scene->AddObserver(vtkRPScene::NodeAddedEvent, onAdded);
  std::vector<pollfd> fds;
  for (int fd : logic->GetReadyFds()) fds.push_back({fd, POLLIN, 0});
  const double start = SteadySeconds();
  double nextTick = start;
  const double tick = mode == SceneMode::LibraryTimer ? 0.005 : 1.0 / 60.0;
  while (!done) {
    if (wakeOnData) {
      ::poll(fds.data(), fds.size(), 16);
    } else {
      nextTick += tick;
      const double wait = nextTick - SteadySeconds();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
    sink.Measure = SteadySeconds() - start > 0.5;  // after the tools exist and the client settled
    if (library)
      library->Import(scene);
    else
      logic->UpdateNodes(SteadySeconds());
  }
  sender.join();
  library.reset();
  server->CloseSocket();
  r.Sent = sent;
  r.P50 = IgtlClient::HistogramPercentile(r.Histogram, 0.50);
  r.P99 = IgtlClient::HistogramPercentile(r.Histogram, 0.99);
  r.P999 = IgtlClient::HistogramPercentile(r.Histogram, 0.999);
  r.Max = IgtlClient::HistogramPercentile(r.Histogram, 1.0);
  return r;
}

bench::Series Cdf(const std::string& name, const std::vector<uint64_t>& histogram) {
  bench::Series s;
  s.Name = name;
  uint64_t total = 0, running = 0;
  for (uint64_t c : histogram) total += c;
  for (size_t i = 0; i < histogram.size() && total; ++i) {
    if (!histogram[i]) continue;
    running += histogram[i];
    s.X.push_back((static_cast<double>(i) + 1) * 1e-3);
    s.Y.push_back(100.0 * static_cast<double>(running) / static_cast<double>(total));
  }
  return s;
}

// ---------------------------------------------------------------- serial polling CPU

struct SerialResult {
  std::string Mode;
  double Seconds = 0, CpuSeconds = 0, CorePercent = 0, FramesPerSecond = 0;
  uint64_t Frames = 0, Gaps = 0, CrcErrors = 0, Timeouts = 0;
};

SerialResult RunSerial(bool binary, double seconds) {
  PolarisSimulator::Options so;
  so.FrameRate = 60;
  so.NoiseMm = 0.05;
  PolarisSimulator sim(so);
  std::vector<NdiTracker::Tool> tools;
  for (const char* name : {"Stylus", "Reference", "Pointer"}) {
    const auto d = ReadToolDefinition(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/" + name + ".json");
    sim.AddTool(d);
    tools.push_back({d.Name, d.Rom});
  }
  std::string error;
  if (!sim.Start(error)) throw std::runtime_error(error);
  NdiTracker::Options o;
  o.Port = sim.PortPath();
  o.Tools = tools;
  o.Binary = binary;
  o.PollHz = 60;
  NdiTracker tracker(o);
  tracker.Start();
  while (tracker.GetState() != NdiTracker::State::Tracking) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto before = tracker.GetStatistics();
  const double start = SteadySeconds();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const auto after = tracker.GetStatistics();
  SerialResult r;
  r.Mode = binary ? "BX:0801 (binary)" : "TX:0001 (text)";
  r.Seconds = SteadySeconds() - start;
  r.CpuSeconds = after.ThreadCpuSeconds - before.ThreadCpuSeconds;
  r.CorePercent = 100.0 * r.CpuSeconds / r.Seconds;
  r.Frames = after.Frames - before.Frames;
  r.FramesPerSecond = static_cast<double>(r.Frames) / r.Seconds;
  r.Gaps = after.FrameGaps - before.FrameGaps;
  r.CrcErrors = after.CrcErrors - before.CrcErrors;
  r.Timeouts = after.Timeouts - before.Timeouts;
  tracker.Stop();
  sim.Stop();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();

  const std::string dir = bench::OutputDirectory();
  nlohmann::json doc;
  IngestionResult ours = RunOurClient();
  IngestionResult library = RunLibraryLoop();
  std::vector<bench::Series> cdf;
  for (IngestionResult* r : {&ours, &library}) {
    Summarise(*r);
    doc["ingestion"].push_back({{"receiver", r->Receiver},
                                {"tools", kTools},
                                {"throughputMsgPerSecond", r->ThroughputPerSecond},
                                {"pacedRateMsgPerSecond", 20000},
                                {"latencyP50Ms", r->P50 * 1e3},
                                {"latencyP99Ms", r->P99 * 1e3},
                                {"latencyP999Ms", r->P999 * 1e3},
                                {"latencyMaxMs", r->Max * 1e3},
                                {"socketToBufferP50Ms", r->SocketP50 * 1e3},
                                {"socketToBufferP99Ms", r->SocketP99 * 1e3},
                                {"socketToBufferP999Ms", r->SocketP999 * 1e3},
                                {"sent", r->Sent},
                                {"received", r->Received},
                                {"crcErrors", r->CrcErrors},
                                {"displayDroppedAt60Hz", r->DisplayDropped}});
    std::cout << r->Receiver << ": " << r->ThroughputPerSecond << " TRANSFORM/s (flood), at 20000/s: p50 "
              << r->P50 * 1e3 << " ms, p99 " << r->P99 * 1e3 << " ms, p99.9 " << r->P999 * 1e3 << " ms; received "
              << r->Received << "/" << r->Sent;
    if (r->SocketP99 >= 0)
      std::cout << "; socket-to-buffer p50 " << r->SocketP50 * 1e3 << " ms, p99 " << r->SocketP99 * 1e3 << " ms, p99.9 "
                << r->SocketP999 * 1e3 << " ms";
    std::cout << "\n";
    bench::Series s;
    s.Name = r->Receiver + ", sender to buffer";
    uint64_t total = 0, running = 0;
    for (uint64_t c : r->Histogram) total += c;
    for (size_t i = 0; i < r->Histogram.size() && total; ++i) {
      if (!r->Histogram[i]) continue;
      running += r->Histogram[i];
      s.X.push_back((static_cast<double>(i) + 1) * 1e-3);
      s.Y.push_back(100.0 * static_cast<double>(running) / static_cast<double>(total));
    }
    cdf.push_back(s);
  }
  // Sender to scene: 10 tools at 60 Hz for 20 s, each way.
  std::vector<SceneLatency> scene;
  for (SceneMode mode : {SceneMode::WokenByData, SceneMode::Timer60Hz, SceneMode::LibraryTimer})
    scene.push_back(RunSenderToScene(mode, bench::QuickRun() ? 0.7 : 20));
  std::vector<bench::Series> sceneCdf;
  for (const auto& r : scene) {
    doc["senderToScene"].push_back({{"mode", r.Mode}, {"tools", kTools}, {"rateHz", 60}, {"sent", r.Sent},
                                    {"nodeUpdates", r.Updates}, {"p50Ms", r.P50 * 1e3}, {"p99Ms", r.P99 * 1e3},
                                    {"p999Ms", r.P999 * 1e3}, {"maxMs", r.Max * 1e3}});
    std::cout << "sender to scene (" << r.Mode << "), 10 tools at 60 Hz: p50 " << r.P50 * 1e3 << " ms, p99 "
              << r.P99 * 1e3 << " ms, p99.9 " << r.P999 * 1e3 << " ms, max " << r.Max * 1e3 << " ms; " << r.Updates
              << " node updates of " << r.Sent << " poses sent\n";
    sceneCdf.push_back(Cdf(r.Mode, r.Histogram));
  }
  doc["library"] = ROBOPLAN_IGTL_LIBRARY_NAME;
  const double serialSeconds = bench::QuickRun() ? 0.3 : 5;
  std::vector<SerialResult> serial = {RunSerial(true, serialSeconds), RunSerial(false, serialSeconds)};
  for (const auto& s : serial) {
    doc["serial"].push_back({{"mode", s.Mode}, {"seconds", s.Seconds}, {"threadCpuSeconds", s.CpuSeconds},
                             {"corePercent", s.CorePercent}, {"framesPerSecond", s.FramesPerSecond},
                             {"frameGaps", s.Gaps}, {"crcErrors", s.CrcErrors}, {"timeouts", s.Timeouts}});
    std::cout << "serial " << s.Mode << " at 60 Hz: " << s.CorePercent << " % of a core, " << s.FramesPerSecond
              << " replies/s, gaps " << s.Gaps << "\n";
  }
  std::string error;
  rp::bench::FinishConditions(dir, "rpTrackingBenchmark");  // the load after, the steal over the run
  bench::WriteFiguresJSON(dir + "/tracking_benchmark.json", doc, error);
  std::vector<std::vector<double>> rows;
  for (size_t i = 0; i < ours.Histogram.size(); ++i)
    if (ours.Histogram[i] || library.Histogram[i])
      rows.push_back({static_cast<double>(i + 1), static_cast<double>(ours.Histogram[i]), static_cast<double>(library.Histogram[i])});
  bench::WriteCSV(dir + "/tracking_latency_histogram.csv", {"latency_us", "roboplan_count", "library_count"}, rows, error);
  rows.clear();
  for (const auto& r : {ours, library})
    rows.push_back({r.ThroughputPerSecond, r.P50 * 1e3, r.P99 * 1e3, r.P999 * 1e3});
  bench::WriteCSV(dir + "/tracking_ingestion.csv", {"throughput_msg_per_s", "p50_ms", "p99_ms", "p999_ms"}, rows, error);
  rows.clear();
  for (const auto& s : serial) rows.push_back({s.CorePercent, s.FramesPerSecond, static_cast<double>(s.Gaps)});
  bench::WriteCSV(dir + "/tracking_serial_cpu.csv", {"core_percent", "replies_per_s", "frame_gaps"}, rows, error);
  bench::ChartOptions chart;
  {
    bench::Series s;
    s.Name = "RoboPlan IgtlClient, kernel receive to buffer";
    uint64_t total = 0, running = 0;
    for (uint64_t c : ours.SocketHistogram) total += c;
    for (size_t i = 0; i < ours.SocketHistogram.size() && total; ++i) {
      if (!ours.SocketHistogram[i]) continue;
      running += ours.SocketHistogram[i];
      s.X.push_back((static_cast<double>(i) + 1) * 1e-3);
      s.Y.push_back(100.0 * static_cast<double>(running) / static_cast<double>(total));
    }
    cdf.push_back(s);
  }
  {
    bench::ChartOptions sceneChart;
    sceneChart.Title = "Sender to scene: 10 tools at 60 Hz through OpenIGTLink (loopback)";
    sceneChart.XLabel = "sender time stamp to tool node modified (ms)";
    sceneChart.YLabel = "node updates at or below (%)";
    sceneChart.LogX = true;
    bench::WriteChartPNG(dir + "/tracking_sender_to_scene_cdf.png", sceneCdf, sceneChart, error);
    std::vector<std::vector<double>> sceneRows;
    for (size_t i = 0; i < scene[0].Histogram.size(); ++i)
      if (scene[0].Histogram[i] || scene[1].Histogram[i] || scene[2].Histogram[i])
        sceneRows.push_back({static_cast<double>(i + 1), static_cast<double>(scene[0].Histogram[i]),
                             static_cast<double>(scene[1].Histogram[i]), static_cast<double>(scene[2].Histogram[i])});
    bench::WriteCSV(dir + "/tracking_sender_to_scene.csv",
                    {"latency_us", "roboplan_woken_by_data", "roboplan_timer_60hz", "library_thread_timer_5ms"}, sceneRows, error);
  }
  chart.Title = "OpenIGTLink TRANSFORM latency (20,000 msg/s, 10 tools, loopback)";
  chart.XLabel = "latency (ms)";
  chart.YLabel = "messages at or below (%)";
  chart.LogX = true;
  bench::WriteChartPNG(dir + "/tracking_latency_cdf.png", cdf, chart, error);
  std::cout << "figures in " << dir << "\n";
  return 0;
}
