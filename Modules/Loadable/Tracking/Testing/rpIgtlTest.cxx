// OpenIGTLink: wire format against the OpenIGTLink library, and the client/server end to end on
// loopback against peers built with the library (ephemeral ports), including malformed,
// truncated and oversized messages, keep-alives, reconnect back-off and v3 metadata.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <thread>

#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlPositionMessage.h>
#include <igtlQuaternionTrackingDataMessage.h>
#include <igtlServerSocket.h>
#include <igtlStatusMessage.h>
#include <igtlTrackingDataMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_util.h>

#include "rpIgtlClient.h"
#include "rpIgtlProtocol.h"
#include "rpIgtlServer.h"
#include "rpTrackingTestHelpers.h"

using namespace rp;
using test::FreePort;
using test::TestMatrix;
using test::WaitFor;

namespace {

std::vector<uint8_t> PackTransform(const char* name, const double m[16]) {
  auto msg = ::igtl::TransformMessage::New();
  msg->SetDeviceName(name);
  ::igtl::Matrix4x4 mm;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) mm[r][k] = static_cast<float>(m[4 * r + k]);
  msg->SetMatrix(mm);
  msg->SetTimeStamp(static_cast<unsigned int>(WallSeconds()), 0);
  msg->Pack();
  const uint8_t* p = static_cast<const uint8_t*>(msg->GetPackPointer());
  return std::vector<uint8_t>(p, p + msg->GetPackSize());
}

bool SendBytes(::igtl::ClientSocket* socket, const std::vector<uint8_t>& bytes) {
  return socket->Send(bytes.data(), static_cast<int>(bytes.size())) != 0;
}

// A peer built with the OpenIGTLink library: accepts connections and runs a script on each.
class LibraryServer {
 public:
  using Script = std::function<void(::igtl::ClientSocket*, int connection)>;
  explicit LibraryServer(Script script) : Run(std::move(script)) {
    Port = FreePort();
    Socket = ::igtl::ServerSocket::New();
    EXPECT_EQ(Socket->CreateServer(Port), 0);
    Thread = std::thread([this] {
      for (int connection = 0; !Stop; ++connection) {
        ::igtl::ClientSocket::Pointer client;
        while (!Stop && !(client = Socket->WaitForConnection(50))) {
        }
        if (!client) return;
        Run(client, connection);
        client->CloseSocket();
      }
    });
  }
  ~LibraryServer() {
    Stop = true;
    Thread.join();
    Socket->CloseSocket();
  }
  int Port = 0;
  std::atomic<bool> Stop{false};

 private:
  Script Run;
  ::igtl::ServerSocket::Pointer Socket;
  std::thread Thread;
};

ToolPose Newest(const IgtlClient& client, const char* name, uint64_t* count = nullptr) {
  return test::Newest(client.Poses(), name, count);
}
IgtlClient::Options ClientOptions(int port) { return test::LoopbackClientOptions(port); }

void ExpectMatrixNear(const ToolPose& pose, const double m[16], double tol) {
  double got[16];
  pose.ToMatrix(got);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(got[i], m[i], tol) << "element " << i;
}

}  // namespace

TEST(IgtlWire, Crc64MatchesTheNotesAndTheLibrary) {
  EXPECT_EQ(rp::igtl::Crc64("123456789", 9), 0x6C40DF5F0B497347ull);
  std::mt19937 rng(7);
  std::vector<uint8_t> data(1000);
  for (auto& b : data) b = static_cast<uint8_t>(rng());
  EXPECT_EQ(rp::igtl::Crc64(data.data(), data.size()), crc64(data.data(), data.size(), 0));
}

TEST(IgtlWire, LibraryTransformDecodes) {
  double m[16];
  TestMatrix(m);
  const auto bytes = PackTransform("StylusToTracker", m);
  rp::igtl::Header h;
  ASSERT_EQ(rp::igtl::ParseHeader(bytes.data(), h, 1 << 20), rp::igtl::Status::Ok);
  EXPECT_TRUE(h.Is("TRANSFORM"));
  EXPECT_STREQ(h.DeviceName, "StylusToTracker");
  EXPECT_EQ(h.BodySize, 48u);
  EXPECT_EQ(h.Crc, rp::igtl::Crc64(bytes.data() + 58, 48));
  double got[16];
  ASSERT_EQ(rp::igtl::DecodeTransform(bytes.data() + 58, 48, got), rp::igtl::Status::Ok);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(got[i], m[i], 1e-4) << i;
  EXPECT_EQ(rp::igtl::DecodeTransform(bytes.data() + 58, 40, got), rp::igtl::Status::BadBody);
}

TEST(IgtlWire, V3MetadataRoundTripAndLibraryReadsOurV1) {
  double m[16];
  TestMatrix(m);
  const auto content = rp::igtl::EncodeTransform(m);
  const auto v3 = rp::igtl::BuildMessage(2, "TRANSFORM", "StylusTipToReferenc", 1000.5, content.data(), content.size(),
                                     {{"TransformStatus", "MISSING"}, {"IGTL_DEVICE_NAME", "StylusTipToReferenceLongName"}}, 7);
  rp::igtl::Header h;
  ASSERT_EQ(rp::igtl::ParseHeader(v3.data(), h, 1 << 20), rp::igtl::Status::Ok);
  EXPECT_EQ(h.Version, 2);
  EXPECT_DOUBLE_EQ(h.TimestampSeconds(), 1000.5);
  rp::igtl::Body body;
  ASSERT_EQ(rp::igtl::SplitBody(h, v3.data() + 58, body), rp::igtl::Status::Ok);
  EXPECT_EQ(body.ContentSize, 48u);
  EXPECT_EQ(body.MessageId, 7u);
  uint32_t n;
  const char* v = body.Find("IGTL_DEVICE_NAME", n);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(std::string(v, n), "StylusTipToReferenceLongName");
  // Metadata sizes that overrun the body are refused.
  auto bad = v3;
  bad[58 + 7] = 0xFF;  // metadata size low byte
  rp::igtl::ParseHeader(bad.data(), h, 1 << 20);
  EXPECT_EQ(rp::igtl::SplitBody(h, bad.data() + 58, body), rp::igtl::Status::BadMetadata);

  // Our v1 framing is what the library unpacks, CRC included.
  const auto v1 = rp::igtl::BuildMessage(1, "TRANSFORM", "StylusToTracker", 1000.5, content.data(), content.size());
  auto header = ::igtl::MessageHeader::New();
  header->InitPack();
  std::memcpy(header->GetPackPointer(), v1.data(), 58);
  header->Unpack();
  auto msg = ::igtl::TransformMessage::New();
  msg->SetMessageHeader(header);
  msg->AllocatePack();
  std::memcpy(msg->GetPackBodyPointer(), v1.data() + 58, 48);
  EXPECT_TRUE(msg->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY);
  ::igtl::Matrix4x4 mm;
  msg->GetMatrix(mm);
  EXPECT_NEAR(mm[0][3], m[3], 1e-4);
  EXPECT_NEAR(mm[1][0], m[4], 1e-6);
}

TEST(IgtlWire, HeaderRejectsGarbageAndOversized) {
  uint8_t garbage[58];
  std::memset(garbage, 0xEE, sizeof garbage);
  rp::igtl::Header h;
  EXPECT_EQ(rp::igtl::ParseHeader(garbage, h, 1 << 20), rp::igtl::Status::BadHeader);
  double m[16];
  TestMatrix(m);
  auto bytes = PackTransform("X", m);
  bytes[42] = 0x01;  // body size ~ 2^56
  EXPECT_EQ(rp::igtl::ParseHeader(bytes.data(), h, 1 << 20), rp::igtl::Status::Oversized);
}

TEST(IgtlWire, RandomisedParsersNeverCrash) {
  std::mt19937 rng(99);
  double m[16];
  TestMatrix(m);
  const auto content = rp::igtl::EncodeTransform(m);
  const auto seed = rp::igtl::BuildMessage(2, "TRANSFORM", "T", 1.0, content.data(), content.size(), {{"TransformStatus", "OK"}});
  int rejected = 0;
  for (int i = 0; i < 20000; ++i) {
    // One changed byte in the size, CRC or body fields (the rest of a header is free text), and
    // possibly a cut: the header check or the CRC must catch every one.
    std::vector<uint8_t> data = seed;
    data[42 + rng() % (data.size() - 42)] ^= static_cast<uint8_t>(1 + rng() % 255);
    if (rng() % 2) data.resize(58 + rng() % (data.size() - 57));
    std::unique_ptr<uint8_t[]> exact(new uint8_t[data.size()]);
    std::memcpy(exact.get(), data.data(), data.size());
    rp::igtl::Header h;
    if (rp::igtl::ParseHeader(exact.get(), h, 1 << 20) != rp::igtl::Status::Ok || h.BodySize > data.size() - 58) {
      ++rejected;
      continue;
    }
    rp::igtl::Body body;
    if (rp::igtl::Crc64(exact.get() + 58, h.BodySize) != h.Crc) ++rejected;
    if (rp::igtl::SplitBody(h, exact.get() + 58, body) == rp::igtl::Status::Ok) {
      double out[16], p[3], q[4];
      rp::igtl::DecodeTransform(body.Content, body.ContentSize, out);
      rp::igtl::DecodePosition(body.Content, body.ContentSize, p, q);
      int count;
      if (rp::igtl::CountElements(body.ContentSize, 50, count) == rp::igtl::Status::Ok)
        for (int k = 0; k < count; ++k) {
          rp::igtl::TrackingElement te;
          rp::igtl::DecodeQtDataElement(body.Content + 50 * k, te);
        }
    }
  }
  EXPECT_EQ(rejected, 20000);  // every mutation is caught by the header check or the CRC
}

TEST(IgtlClientE2E, ReadsEveryTrackingTypeFromALibraryServer) {
  double m[16], m2[16];
  TestMatrix(m);
  TestMatrix(m2, 100);
  LibraryServer server([&](::igtl::ClientSocket* s, int) {
    SendBytes(s, PackTransform("StylusToTracker", m));
    auto pos = ::igtl::PositionMessage::New();
    pos->SetDeviceName("NeedleToTracker");
    pos->SetPosition(1.f, 2.f, 3.f);
    pos->SetQuaternion(0.f, 0.f, std::sqrt(0.5f), std::sqrt(0.5f));
    pos->Pack();
    s->Send(pos->GetPackPointer(), pos->GetPackSize());
    auto td = ::igtl::TrackingDataMessage::New();
    td->SetDeviceName("Tracker");
    for (const char* name : {"ReferenceToTracker", "PointerToTracker"}) {
      auto e = ::igtl::TrackingDataElement::New();
      e->SetName(name);
      e->SetType(::igtl::TrackingDataElement::TYPE_6D);
      ::igtl::Matrix4x4 mm;
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) mm[r][k] = static_cast<float>(m2[4 * r + k]);
      e->SetMatrix(mm);
      td->AddTrackingDataElement(e);
    }
    td->Pack();
    s->Send(td->GetPackPointer(), td->GetPackSize());
    auto qt = ::igtl::QuaternionTrackingDataMessage::New();
    qt->SetDeviceName("Tracker");
    auto qe = ::igtl::QuaternionTrackingDataElement::New();
    qe->SetName("ProbeToTracker");
    qe->SetPosition(4.f, 5.f, 6.f);
    qe->SetQuaternion(std::sqrt(0.5f), 0.f, 0.f, std::sqrt(0.5f));
    qt->AddQuaternionTrackingDataElement(qe);
    qt->Pack();
    s->Send(qt->GetPackPointer(), qt->GetPackSize());
    auto st = ::igtl::StatusMessage::New();
    st->SetDeviceName("Tracker");
    st->SetCode(::igtl::StatusMessage::STATUS_OK);
    st->Pack();
    s->Send(st->GetPackPointer(), st->GetPackSize());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  });
  IgtlClient client(ClientOptions(server.Port));
  client.Start();
  ASSERT_TRUE(WaitFor([&] { return client.GetStatistics().StatusMessages >= 1; }, 3)) << client.LastError();
  ExpectMatrixNear(Newest(client, "StylusToTracker"), m, 1e-4);
  EXPECT_EQ(Newest(client, "StylusToTracker").State, ToolState::OK);
  const ToolPose needle = Newest(client, "NeedleToTracker");
  EXPECT_NEAR(needle.Translation[2], 3.0, 1e-6);
  EXPECT_NEAR(needle.Quaternion[0], std::sqrt(0.5), 1e-6);  // w
  EXPECT_NEAR(needle.Quaternion[3], std::sqrt(0.5), 1e-6);  // z
  ExpectMatrixNear(Newest(client, "ReferenceToTracker"), m2, 1e-4);
  ExpectMatrixNear(Newest(client, "PointerToTracker"), m2, 1e-4);
  const ToolPose probe = Newest(client, "ProbeToTracker");
  EXPECT_NEAR(probe.Translation[1], 5.0, 1e-6);
  EXPECT_NEAR(probe.Quaternion[1], std::sqrt(0.5), 1e-6);  // x
  const auto stats = client.GetStatistics();
  EXPECT_EQ(stats.Poses, 5u);
  EXPECT_EQ(stats.CrcErrors + stats.Malformed, 0u);
  EXPECT_EQ(stats.LastStatusCode, 1);
}

TEST(IgtlClientE2E, BadMessagesAreNamedAndTheConnectionSurvivesOrRestarts) {
  double m[16];
  TestMatrix(m);
  LibraryServer server([&](::igtl::ClientSocket* s, int connection) {
    if (connection == 0) {
      // A TRANSFORM with a short body (CRC valid): malformed, the stream stays in step.
      const auto content = rp::igtl::EncodeTransform(m);
      SendBytes(s, rp::igtl::BuildMessage(1, "TRANSFORM", "ShortToTracker", WallSeconds(), content.data(), 40));
      // A CRC fault.
      auto corrupt = PackTransform("CorruptToTracker", m);
      corrupt.back() ^= 0x01;
      SendBytes(s, corrupt);
      // An unknown type is skipped.
      const uint8_t blob[5] = {1, 2, 3, 4, 5};
      SendBytes(s, rp::igtl::BuildMessage(1, "CUSTOM", "Blob", WallSeconds(), blob, 5));
      SendBytes(s, PackTransform("GoodToTracker", m));
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      // Oversized: the client cannot trust the stream any more and hangs up.
      auto huge = PackTransform("HugeToTracker", m);
      huge[42] = 0x7F;
      SendBytes(s, huge);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    } else if (connection == 1) {
      // Half a message, then the connection closes: truncated.
      const auto bytes = PackTransform("HalfToTracker", m);
      s->Send(bytes.data(), 70);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } else if (connection == 2) {
      uint8_t garbage[200];
      std::memset(garbage, 0xEE, sizeof garbage);
      s->Send(garbage, sizeof garbage);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } else {
      SendBytes(s, PackTransform("AfterToTracker", m));
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
  });
  IgtlClient client(ClientOptions(server.Port));
  client.Start();
  ASSERT_TRUE(WaitFor([&] { return Newest(client, "GoodToTracker").State == ToolState::OK &&
                                    client.Poses().Find("GoodToTracker", 13) >= 0; }, 3));
  auto stats = client.GetStatistics();
  EXPECT_EQ(stats.Malformed, 1u);
  EXPECT_EQ(stats.CrcErrors, 1u);
  EXPECT_EQ(stats.Skipped, 1u);
  EXPECT_EQ(stats.Connections, 1u);  // all of that on one connection
  EXPECT_LT(client.Poses().Find("ShortToTracker", 14), 0);
  EXPECT_LT(client.Poses().Find("CorruptToTracker", 16), 0);
  ASSERT_TRUE(WaitFor([&] { return client.GetStatistics().Oversized == 1; }, 2));
  EXPECT_NE(client.LastError().find("oversized TRANSFORM"), std::string::npos) << client.LastError();
  ASSERT_TRUE(WaitFor([&] { return client.Poses().Find("AfterToTracker", 14) >= 0; }, 5)) << client.LastError();
  stats = client.GetStatistics();
  EXPECT_EQ(stats.Connections, 4u);
  EXPECT_EQ(stats.Malformed, 2u);  // + the garbage header
  EXPECT_LT(client.Poses().Find("HalfToTracker", 13), 0);
}

TEST(IgtlClientE2E, KeepAliveAndReconnectBackOff) {
  std::atomic<int> getStatusSeen{0};
  LibraryServer server([&](::igtl::ClientSocket* s, int) {
    // Silent peer: wait for the client's GET_STATUS keep-alive and answer with STATUS.
    auto header = ::igtl::MessageHeader::New();
    s->SetReceiveTimeout(1000);
    header->InitPack();
    if (s->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return;
    header->Unpack();
    if (std::strcmp(header->GetDeviceType(), "GET_STATUS") == 0) {
      ++getStatusSeen;
      auto st = ::igtl::StatusMessage::New();
      st->SetDeviceName("Peer");
      st->SetCode(::igtl::StatusMessage::STATUS_OK);
      st->Pack();
      s->Send(st->GetPackPointer(), st->GetPackSize());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  });
  // v1 headers by default: Debian's library (a protocol-2 build) cannot decode v3 framing, so
  // v2 headers are opt-in (to get PLUS's metadata).
  EXPECT_EQ(IgtlClient::Options().HeaderVersion, 1);
  {
    auto options = ClientOptions(server.Port);
    options.KeepAliveSeconds = 0.2;
    IgtlClient client(options);
    client.Start();
    ASSERT_TRUE(WaitFor([&] { return client.GetStatistics().StatusMessages >= 1; }, 3)) << client.LastError();
    EXPECT_EQ(getStatusSeen.load(), 1);
    EXPECT_GE(client.GetStatistics().KeepAlivesSent, 1u);
    client.Stop();
  }

  // Nobody listening: attempts back off (0.1, 0.2, 0.4, 0.8 ... s), never a busy loop.
  auto absent = ClientOptions(FreePort());
  absent.ReconnectInitialSeconds = 0.1;
  absent.ReconnectMaxSeconds = 2.0;
  IgtlClient lonely(absent);
  lonely.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const uint64_t attempts = lonely.GetStatistics().ConnectAttempts;
  lonely.Stop();
  EXPECT_GE(attempts, 3u);
  EXPECT_LE(attempts, 5u);
  EXPECT_NE(lonely.LastError().find("cannot connect"), std::string::npos) << lonely.LastError();
}

TEST(IgtlServerE2E, LibraryClientReceivesTransformsAndTrackingData) {
  ToolPoseTable table;
  const int stylus = table.FindOrAdd("StylusToTracker");
  const int reference = table.FindOrAdd("ReferenceToTracker");
  double m[16];
  TestMatrix(m);
  ToolPose pose;
  pose.FromMatrix(m);
  pose.State = ToolState::OK;
  ToolPose missing;
  missing.State = ToolState::Missing;
  IgtlServer::Options options;
  options.Port = 0;
  IgtlServer server(table, options);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  ASSERT_GT(server.Port(), 0);

  auto socket = ::igtl::ClientSocket::New();
  ASSERT_EQ(socket->ConnectToServer("127.0.0.1", server.Port()), 0);
  ASSERT_TRUE(WaitFor([&] { return server.ClientCount() == 1; }, 2));
  table.Publish(stylus, pose);
  table.Publish(reference, missing);
  socket->SetReceiveTimeout(2000);
  auto receive = [&](const char* type, std::vector<uint8_t>& body, ::igtl::MessageHeader::Pointer& header) {
    for (int i = 0; i < 50; ++i) {
      header = ::igtl::MessageHeader::New();
      header->InitPack();
      if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return false;
      header->Unpack();
      body.resize(static_cast<size_t>(header->GetBodySizeToRead()));
      if (!body.empty() && socket->Receive(body.data(), static_cast<int>(body.size())) != static_cast<int>(body.size())) return false;
      if (std::strcmp(header->GetDeviceType(), type) == 0) return true;
    }
    return false;
  };
  std::vector<uint8_t> body;
  ::igtl::MessageHeader::Pointer header;
  ASSERT_TRUE(receive("TRANSFORM", body, header));
  {
    const uint8_t* raw = static_cast<const uint8_t*>(header->GetPackPointer());  // byte-swapped in place by Unpack
    EXPECT_EQ(raw[0] | raw[1], 1);  // v1 until the client speaks v2
  }
  EXPECT_STREQ(header->GetDeviceName(), "StylusToTracker");  // the missing reference stays silent
  auto transform = ::igtl::TransformMessage::New();
  transform->SetMessageHeader(header);
  transform->AllocatePack();
  std::memcpy(transform->GetPackBodyPointer(), body.data(), body.size());
  ASSERT_TRUE(transform->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY);  // CRC checked
  ::igtl::Matrix4x4 mm;
  transform->GetMatrix(mm);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(mm[r][k], m[4 * r + k], 1e-4);

  auto start = ::igtl::StartTrackingDataMessage::New();
  start->SetDeviceName("Client");
  start->SetResolution(20);
  start->SetCoordinateName("Tracker");
  start->Pack();
  socket->Send(start->GetPackPointer(), start->GetPackSize());
  ASSERT_TRUE(receive("RTS_TDATA", body, header));
  EXPECT_EQ(body.at(0), 0);
  ASSERT_TRUE(receive("TDATA", body, header));
  EXPECT_EQ(body.size() % 70, 0u);
  EXPECT_EQ(body.size() / 70, 1u);  // only the valid stylus: TDATA has no status field
  auto stopData = ::igtl::StopTrackingDataMessage::New();
  stopData->SetDeviceName("Client");
  stopData->Pack();
  socket->Send(stopData->GetPackPointer(), stopData->GetPackSize());
  ASSERT_TRUE(receive("RTS_TDATA", body, header));
  ASSERT_TRUE(receive("STATUS", body, header));  // keep-alive once nothing new is sent
  socket->CloseSocket();
  server.Stop();
}

TEST(IgtlServerE2E, OurClientGetsV3MetadataAndMissingStatus) {
  ToolPoseTable table;
  const int stylus = table.FindOrAdd("StylusToTracker");
  const int longName = table.FindOrAdd("StylusTipOfTheLongProbeToTracker");
  IgtlServer::Options options;
  options.Port = 0;
  IgtlServer server(table, options);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  auto clientOptions = ClientOptions(server.Port());
  clientOptions.HeaderVersion = 2;
  clientOptions.RequestQuaternionData = true;  // sends a v2 header: the server switches to v3
  IgtlClient client(clientOptions);
  client.Start();
  ASSERT_TRUE(WaitFor([&] { return client.GetStatistics().RtsMessages >= 1; }, 3)) << client.LastError();
  EXPECT_EQ(client.GetStatistics().LastRtsStatus, 0);
  double m[16];
  TestMatrix(m);
  ToolPose pose;
  pose.FromMatrix(m);
  pose.State = ToolState::OK;
  table.Publish(longName, pose);
  ToolPose missing;
  missing.State = ToolState::Missing;
  table.Publish(stylus, missing);
  ASSERT_TRUE(WaitFor([&] { return client.Poses().Find("StylusTipOfTheLongProbeToTracker", 32) >= 0; }, 2));
  ExpectMatrixNear(Newest(client, "StylusTipOfTheLongProbeToTracker"), m, 1e-4);
  ASSERT_TRUE(WaitFor([&] { return client.Poses().Find("StylusToTracker", 15) >= 0; }, 2));
  EXPECT_EQ(Newest(client, "StylusToTracker").State, ToolState::Missing);
  EXPECT_EQ(client.GetStatistics().CrcErrors, 0u);
  client.Stop();
  server.Stop();
}
