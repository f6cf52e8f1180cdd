// Wire compatibility with upstream OpenIGTLink 3.x, the library PLUS and 3D Slicer's
// OpenIGTLinkIF are built on (the oracle, built from ../shared/oracles into the test tree, with
// the project's sanitizer):
//  * bytes, ours → upstream: every message type we send, header v1 and v2, with and without
//    metadata, is byte-identical to upstream's own Pack and unpacks with upstream (CRC checked)
//    from an exactly sized heap buffer (AddressSanitizer sees any read past our message);
//  * bytes, upstream → ours: every type we read, packed by upstream, decodes to its fields;
//  * sockets, in process: our client against a PLUS-like v2 server made of upstream calls, our
//    server against an upstream v2 client;
//  * sockets, upstream's example programs (the peers users' software is made of): our client
//    against TrackerServer, TrackingDataServer, QuaternionTrackingDataServer, StatusServer,
//    StringServer and ImagerServer (IMAGE into a volume node); our server against
//    ReceiveClient, TrackingDataClient and QuaternionTrackingDataClient.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fstream>
#include <iterator>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpIgtlClient.h"
#include "rpIgtlProtocol.h"
#include "rpIgtlServer.h"
#include "rpPolarisSimulator.h"
#include "rpSharedData.h"
#include "rpTrackingCommands.h"
#include "rpTrackingTestHelpers.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackingLogic.h"

#if ROBOPLAN_UPSTREAM_IGTL
#include <igtlClientSocket.h>
#include <igtlCommandMessage.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlPositionMessage.h>
#include <igtlQuaternionTrackingDataMessage.h>
#include <igtlServerSocket.h>
#include <igtlStatusMessage.h>
#include <igtlStringMessage.h>
#include <igtlTrackingDataMessage.h>
#include <igtlTransformMessage.h>

#include "rpUpstreamReceive.h"
#endif

using namespace rp;
namespace wire = rp::igtl;

#if !ROBOPLAN_UPSTREAM_IGTL

TEST(IgtlUpstream, OracleAvailable) {
  GTEST_SKIP() << "upstream OpenIGTLink 3.x not found at " << ROBOPLAN_UPSTREAM_IGTL_SOURCE
               << " (../shared/oracles/openigtlink-3): the upstream wire tests are skipped";
}

#else

namespace {

constexpr double kStamp = 1732358400.25;  // a fixed send time (2024-11-23 10:40:00.25 UTC)

std::string OutputDir() {
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string Program(const char* name) { return std::string(ROBOPLAN_UPSTREAM_IGTL_BIN) + "/" + name; }

using test::TestMatrix;

void ToUpstream(const double m[16], ::igtl::Matrix4x4 out) {
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) out[r][k] = static_cast<float>(m[4 * r + k]);
}

// Upstream's send path for one message: header version, time stamp, metadata, Pack.
void UpstreamFrame(::igtl::MessageBase* message, int version, const std::vector<wire::MetaPair>& metadata) {
  message->SetHeaderVersion(static_cast<unsigned short>(version));
  const double whole = std::floor(kStamp);
  message->SetTimeStamp(static_cast<unsigned int>(whole), static_cast<unsigned int>((kStamp - whole) * 4294967296.0));
  for (const auto& m : metadata) message->SetMetaDataElement(m.Key, IANA_TYPE_US_ASCII, m.Value);
  message->Pack();
}

std::vector<uint8_t> Bytes(::igtl::MessageBase* message) {
  const uint8_t* p = static_cast<const uint8_t*>(message->GetPackPointer());
  return std::vector<uint8_t>(p, p + message->GetPackSize());
}

// Upstream's receive path (what ReceiveClient, PLUS and Slicer do): header, then a body buffer
// of exactly the announced size, then Unpack with the CRC check.
template <class M>
typename M::Pointer UpstreamUnpack(const std::vector<uint8_t>& bytes, int& result) {
  auto header = ::igtl::MessageHeader::New();
  header->InitBuffer();
  std::memcpy(header->GetBufferPointer(), bytes.data(), IGTL_HEADER_SIZE);
  header->Unpack();
  auto message = M::New();
  message->SetMessageHeader(header);
  message->AllocateBuffer();
  EXPECT_EQ(message->GetBufferBodySize(), bytes.size() - IGTL_HEADER_SIZE);
  std::memcpy(message->GetBufferBodyPointer(), bytes.data() + IGTL_HEADER_SIZE, bytes.size() - IGTL_HEADER_SIZE);
  result = message->Unpack(1);
  return message;
}

struct Framing {
  int Version;
  bool Metadata;
};
std::string Name(const ::testing::TestParamInfo<Framing>& info) {
  return "HeaderV" + std::to_string(info.param.Version) + (info.param.Metadata ? "WithMetadata" : "NoMetadata");
}

// Metadata in key order: upstream keeps it in a std::map, so its bytes come sorted.
const std::vector<wire::MetaPair> kMetadata = {{"IGTL_DEVICE_NAME", "StylusTipOfTheLongProbeToTracker"},
                                               {"TransformStatus", "MISSING"}};

class OursToUpstream : public ::testing::TestWithParam<Framing> {
 protected:
  std::vector<wire::MetaPair> Metadata() const {
    return GetParam().Metadata ? kMetadata : std::vector<wire::MetaPair>{};
  }
  // Our framing of a content, as the client and server write it.
  std::vector<uint8_t> Ours(const char* type, const char* device, const std::vector<uint8_t>& content) {
    uint8_t* out = this->Writer.Begin(static_cast<uint16_t>(GetParam().Version), type, device, kStamp, content.size());
    if (!content.empty()) std::memcpy(out, content.data(), content.size());
    const auto meta = this->Metadata();
    this->Writer.Finish(meta.data(), meta.size());
    return std::vector<uint8_t>(this->Writer.Data(), this->Writer.Data() + this->Writer.Size());
  }
  // Upstream reads our metadata back exactly.
  void ExpectMetadata(::igtl::MessageBase* message) {
    if (GetParam().Version < 2) return;
    EXPECT_EQ(message->GetMetaData().size(), this->Metadata().size());
    for (const auto& m : this->Metadata()) {
      std::string value;
      EXPECT_TRUE(message->GetMetaDataElement(m.Key, value)) << m.Key;
      EXPECT_EQ(value, m.Value);
    }
  }
  template <class M>
  void HeaderOnly(const char* type) {
    SCOPED_TRACE(type);
    const auto ours = this->Ours(type, "RoboPlan", {});
    auto reference = M::New();
    reference->SetDeviceName("RoboPlan");
    UpstreamFrame(reference, GetParam().Version, this->Metadata());
    EXPECT_EQ(ours, Bytes(reference));
    if (GetParam().Version >= 2) {
      EXPECT_GE(ours.size(), wire::HeaderSize + wire::ExtendedHeaderSize + 2);
    }
    if (GetParam().Version >= 2 && GetParam().Metadata) {  // upstream unpacks bodies beyond the INDEX_COUNT
      int result = 0;
      auto message = UpstreamUnpack<M>(ours, result);
      ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
      this->ExpectMetadata(message);
    }
  }
  wire::MessageWriter Writer;
};

}  // namespace

// ---------------------------------------------------------------- bytes: ours → upstream

TEST_P(OursToUpstream, Transform) {
  double m[16];
  TestMatrix(m);
  std::vector<uint8_t> content(wire::TransformSize);
  wire::EncodeTransform(m, content.data());
  const auto ours = this->Ours("TRANSFORM", "StylusToTracker", content);
  auto reference = ::igtl::TransformMessage::New();
  reference->SetDeviceName("StylusToTracker");
  ::igtl::Matrix4x4 mm;
  ToUpstream(m, mm);
  reference->SetMatrix(mm);
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));  // byte for byte what upstream sends

  int result = 0;
  auto message = UpstreamUnpack<::igtl::TransformMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY) << "upstream refused our TRANSFORM";
  ::igtl::Matrix4x4 got;
  message->GetMatrix(got);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(got[r][k], static_cast<float>(m[4 * r + k]));
  EXPECT_STREQ(message->GetDeviceName(), "StylusToTracker");
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, Position) {
  const double p[3] = {1.5, -2.25, 300.125}, q[4] = {std::sqrt(0.5), 0, 0, std::sqrt(0.5)};  // w x y z
  std::vector<uint8_t> content(wire::PositionSize);
  wire::EncodePosition(p, q, content.data());
  const auto ours = this->Ours("POSITION", "NeedleToTracker", content);
  auto reference = ::igtl::PositionMessage::New();
  reference->SetDeviceName("NeedleToTracker");
  reference->SetPosition(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
  reference->SetQuaternion(static_cast<float>(q[1]), static_cast<float>(q[2]), static_cast<float>(q[3]), static_cast<float>(q[0]));
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));
  int result = 0;
  auto message = UpstreamUnpack<::igtl::PositionMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  float position[3], quaternion[4];
  message->GetPosition(position);
  message->GetQuaternion(quaternion);
  EXPECT_FLOAT_EQ(position[2], 300.125f);
  EXPECT_FLOAT_EQ(quaternion[2], static_cast<float>(std::sqrt(0.5)));  // z
  EXPECT_FLOAT_EQ(quaternion[3], static_cast<float>(std::sqrt(0.5)));  // w
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, TrackingData) {
  double m[16], m2[16];
  TestMatrix(m);
  TestMatrix(m2, 100);
  std::vector<uint8_t> content(2 * wire::TDataElementSize);
  wire::EncodeTDataElement("StylusToTracker", wire::TrackingType6D, m, content.data());
  wire::EncodeTDataElement("ReferenceToTracker", wire::TrackingType6D, m2, content.data() + wire::TDataElementSize);
  const auto ours = this->Ours("TDATA", "Tracker", content);
  auto reference = ::igtl::TrackingDataMessage::New();
  reference->SetDeviceName("Tracker");
  for (const auto& [name, matrix] : {std::make_pair("StylusToTracker", m), std::make_pair("ReferenceToTracker", m2)}) {
    auto e = ::igtl::TrackingDataElement::New();
    e->SetName(name);
    e->SetType(::igtl::TrackingDataElement::TYPE_6D);
    ::igtl::Matrix4x4 mm;
    ToUpstream(matrix, mm);
    e->SetMatrix(mm);
    reference->AddTrackingDataElement(e);
  }
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));
  int result = 0;
  auto message = UpstreamUnpack<::igtl::TrackingDataMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  ASSERT_EQ(message->GetNumberOfTrackingDataElements(), 2);
  ::igtl::TrackingDataElement::Pointer e;
  message->GetTrackingDataElement(1, e);
  EXPECT_STREQ(e->GetName(), "ReferenceToTracker");
  EXPECT_EQ(e->GetType(), ::igtl::TrackingDataElement::TYPE_6D);
  ::igtl::Matrix4x4 got;
  e->GetMatrix(got);
  EXPECT_FLOAT_EQ(got[0][3], static_cast<float>(m2[3]));
  EXPECT_FLOAT_EQ(got[2][1], static_cast<float>(m2[9]));
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, QuaternionTrackingData) {
  const double p[3] = {4, 5, 6}, q[4] = {0.5, 0.5, 0.5, 0.5};
  std::vector<uint8_t> content(wire::QtDataElementSize);
  wire::EncodeQtDataElement("ProbeToTracker", wire::TrackingType6D, p, q, content.data());
  const auto ours = this->Ours("QTDATA", "Tracker", content);
  auto reference = ::igtl::QuaternionTrackingDataMessage::New();
  reference->SetDeviceName("Tracker");
  auto e = ::igtl::QuaternionTrackingDataElement::New();
  e->SetName("ProbeToTracker");
  e->SetType(::igtl::QuaternionTrackingDataElement::TYPE_6D);
  e->SetPosition(4.f, 5.f, 6.f);
  e->SetQuaternion(0.5f, 0.5f, 0.5f, 0.5f);
  reference->AddQuaternionTrackingDataElement(e);
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));
  int result = 0;
  auto message = UpstreamUnpack<::igtl::QuaternionTrackingDataMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  ASSERT_EQ(message->GetNumberOfQuaternionTrackingDataElements(), 1);
  ::igtl::QuaternionTrackingDataElement::Pointer got;
  message->GetQuaternionTrackingDataElement(0, got);
  EXPECT_STREQ(got->GetName(), "ProbeToTracker");
  float position[3];
  got->GetPosition(position);
  EXPECT_FLOAT_EQ(position[1], 5.f);
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, Status) {
  const char* text = "tracker connected";
  std::vector<uint8_t> content(wire::StatusSize(text));
  wire::EncodeStatus(wire::StatusOk, 128, "OK!", text, content.data());
  const auto ours = this->Ours("STATUS", "Tracker", content);
  auto reference = ::igtl::StatusMessage::New();
  reference->SetDeviceName("Tracker");
  reference->SetCode(::igtl::StatusMessage::STATUS_OK);
  reference->SetSubCode(128);
  reference->SetErrorName("OK!");
  reference->SetStatusString(text);
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));
  int result = 0;
  auto message = UpstreamUnpack<::igtl::StatusMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_EQ(message->GetCode(), 1);
  EXPECT_EQ(message->GetSubCode(), 128);
  EXPECT_STREQ(message->GetErrorName(), "OK!");
  EXPECT_STREQ(message->GetStatusString(), text);
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, String) {
  const std::string text = "CMD_42 done";
  std::vector<uint8_t> content(wire::StringHeaderSize + text.size());
  wire::EncodeString(text.data(), text.size(), content.data());
  const auto ours = this->Ours("STRING", "Reply", content);
  auto reference = ::igtl::StringMessage::New();
  reference->SetDeviceName("Reply");
  reference->SetString(text);
  UpstreamFrame(reference, GetParam().Version, this->Metadata());
  EXPECT_EQ(ours, Bytes(reference));
  int result = 0;
  auto message = UpstreamUnpack<::igtl::StringMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_STREQ(message->GetString(), text.c_str());
  EXPECT_EQ(message->GetEncoding(), 3);
  this->ExpectMetadata(message);
}

TEST_P(OursToUpstream, StartTrackingData) {
  for (const char* type : {"STT_TDATA", "STT_QTDATA"}) {
    std::vector<uint8_t> content(wire::StartTrackingSize);
    wire::EncodeStartTracking(16, "Tracker", content.data());
    const auto ours = this->Ours(type, "RoboPlan", content);
    int result = 0;
    if (std::string(type) == "STT_TDATA") {
      auto reference = ::igtl::StartTrackingDataMessage::New();
      reference->SetDeviceName("RoboPlan");
      reference->SetResolution(16);
      reference->SetCoordinateName("Tracker");
      UpstreamFrame(reference, GetParam().Version, this->Metadata());
      EXPECT_EQ(ours, Bytes(reference)) << type;
      auto message = UpstreamUnpack<::igtl::StartTrackingDataMessage>(ours, result);
      ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY) << type;
      EXPECT_EQ(message->GetResolution(), 16);
      EXPECT_STREQ(message->GetCoordinateName(), "Tracker");
      this->ExpectMetadata(message);
    } else {
      auto reference = ::igtl::StartQuaternionTrackingDataMessage::New();
      reference->SetDeviceName("RoboPlan");
      reference->SetResolution(16);
      reference->SetCoordinateName("Tracker");
      UpstreamFrame(reference, GetParam().Version, this->Metadata());
      EXPECT_EQ(ours, Bytes(reference)) << type;
      auto message = UpstreamUnpack<::igtl::StartQuaternionTrackingDataMessage>(ours, result);
      ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY) << type;
      EXPECT_EQ(message->GetResolution(), 16);
      EXPECT_STREQ(message->GetCoordinateName(), "Tracker");
      this->ExpectMetadata(message);
    }
  }
}

TEST_P(OursToUpstream, ReadyToSend) {
  std::vector<uint8_t> content(wire::RtsSize);
  wire::EncodeRts(0, content.data());
  int result = 0;
  {
    const auto ours = this->Ours("RTS_TDATA", "Tracker", content);
    auto reference = ::igtl::RTSTrackingDataMessage::New();
    reference->SetDeviceName("Tracker");
    reference->SetStatus(0);
    UpstreamFrame(reference, GetParam().Version, this->Metadata());
    EXPECT_EQ(ours, Bytes(reference));
    auto message = UpstreamUnpack<::igtl::RTSTrackingDataMessage>(ours, result);
    ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
    EXPECT_EQ(message->GetStatus(), 0);
    this->ExpectMetadata(message);
  }
  {
    const auto ours = this->Ours("RTS_QTDATA", "Tracker", content);
    auto reference = ::igtl::RTSQuaternionTrackingDataMessage::New();
    reference->SetDeviceName("Tracker");
    reference->SetStatus(0);
    UpstreamFrame(reference, GetParam().Version, this->Metadata());
    EXPECT_EQ(ours, Bytes(reference));
    auto message = UpstreamUnpack<::igtl::RTSQuaternionTrackingDataMessage>(ours, result);
    ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
    EXPECT_EQ(message->GetStatus(), 0);
  }
}

// GET_STATUS, STP_TDATA, STP_QTDATA: no content. With header version 2 the body is the
// extended header and the metadata header (at least its 2-byte INDEX_COUNT).
TEST_P(OursToUpstream, HeaderOnlyMessages) {
  this->HeaderOnly<::igtl::GetStatusMessage>("GET_STATUS");
  this->HeaderOnly<::igtl::StopTrackingDataMessage>("STP_TDATA");
  this->HeaderOnly<::igtl::StopQuaternionTrackingDataMessage>("STP_QTDATA");
}

INSTANTIATE_TEST_SUITE_P(Framings, OursToUpstream,
                         ::testing::Values(Framing{1, false}, Framing{2, false}, Framing{2, true}), Name);

// The case of issue 13: a v3 TRANSFORM without metadata. RoboPlan used to write
// METADATA_HEADER_SIZE = 0; upstream always reads the 2-byte INDEX_COUNT, past the end of
// such a message (a heap-buffer-overflow under AddressSanitizer). Ours now carries it.
TEST(IgtlUpstreamWire, V3TransformWithoutMetadataCarriesIndexCount) {
  double m[16];
  TestMatrix(m);
  const auto content = wire::EncodeTransform(m);
  const auto ours = wire::BuildMessage(2, "TRANSFORM", "StylusToTracker", kStamp, content.data(), content.size());
  ASSERT_EQ(ours.size(), wire::HeaderSize + wire::ExtendedHeaderSize + wire::TransformSize + 2);
  EXPECT_EQ(ours[wire::HeaderSize + 2], 0);  // METADATA_HEADER_SIZE = 2 (big endian)
  EXPECT_EQ(ours[wire::HeaderSize + 3], 2);
  EXPECT_EQ(ours[ours.size() - 2], 0);  // INDEX_COUNT = 0
  EXPECT_EQ(ours[ours.size() - 1], 0);
  int result = 0;
  auto message = UpstreamUnpack<::igtl::TransformMessage>(ours, result);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_TRUE(message->GetMetaData().empty());
  // And we still read what RoboPlan wrote before the fix (no metadata header at all).
  std::vector<uint8_t> old(ours.begin(), ours.end() - 2);
  old[wire::HeaderSize + 3] = 0;
  wire::Header h;
  ASSERT_EQ(wire::ParseHeader(old.data(), h, 1 << 20), wire::Status::Ok);
  h.BodySize -= 2;
  wire::Body body;
  ASSERT_EQ(wire::SplitBody(h, old.data() + wire::HeaderSize, body), wire::Status::Ok);
  EXPECT_EQ(body.ContentSize, wire::TransformSize);
}

// ---------------------------------------------------------------- bytes: upstream → ours

namespace {
// Our reading of a message; holds the bytes (the body points into them).
struct Decoded {
  std::unique_ptr<std::vector<uint8_t>> Data;
  wire::Header Header;
  wire::Body Body;
};
Decoded OurParse(std::vector<uint8_t> message) {
  Decoded d;
  d.Data = std::make_unique<std::vector<uint8_t>>(std::move(message));
  const std::vector<uint8_t>& bytes = *d.Data;
  EXPECT_EQ(wire::ParseHeader(bytes.data(), d.Header, 1u << 24), wire::Status::Ok);
  EXPECT_EQ(d.Header.BodySize, bytes.size() - wire::HeaderSize);
  EXPECT_EQ(wire::Crc64(bytes.data() + wire::HeaderSize, d.Header.BodySize), d.Header.Crc);
  EXPECT_EQ(wire::SplitBody(d.Header, bytes.data() + wire::HeaderSize, d.Body), wire::Status::Ok);
  EXPECT_NEAR(d.Header.TimestampSeconds(), kStamp, 1e-6);
  return d;
}
void ExpectOurMetadata(const Decoded& d, const Framing& f) {
  if (f.Version < 2 || !f.Metadata) {
    EXPECT_EQ(d.Body.MetaCount, 0);
    return;
  }
  ASSERT_EQ(d.Body.MetaCount, 2);
  uint32_t n = 0;
  const char* v = d.Body.Find("TransformStatus", n);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(std::string(v, n), "MISSING");
}
class UpstreamToOurs : public ::testing::TestWithParam<Framing> {
 protected:
  std::vector<wire::MetaPair> Metadata() const { return GetParam().Metadata ? kMetadata : std::vector<wire::MetaPair>{}; }
};
}  // namespace

TEST_P(UpstreamToOurs, TransformAndPosition) {
  double m[16];
  TestMatrix(m);
  auto t = ::igtl::TransformMessage::New();
  t->SetDeviceName("StylusToTracker");
  ::igtl::Matrix4x4 mm;
  ToUpstream(m, mm);
  t->SetMatrix(mm);
  UpstreamFrame(t, GetParam().Version, this->Metadata());
  const Decoded d = OurParse(Bytes(t));
  EXPECT_EQ(d.Header.Version, GetParam().Version);
  EXPECT_TRUE(d.Header.Is("TRANSFORM"));
  EXPECT_STREQ(d.Header.DeviceName, "StylusToTracker");
  double got[16];
  ASSERT_EQ(wire::DecodeTransform(d.Body.Content, d.Body.ContentSize, got), wire::Status::Ok);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(got[i], m[i], 1e-4) << i;
  ExpectOurMetadata(d, GetParam());

  for (auto type : {::igtl::PositionMessage::POSITION_ONLY, ::igtl::PositionMessage::WITH_QUATERNION3,
                    ::igtl::PositionMessage::ALL}) {
    auto p = ::igtl::PositionMessage::New();
    p->SetDeviceName("NeedleToTracker");
    p->SetPackType(type);
    p->SetPosition(1.f, 2.f, 3.f);
    p->SetQuaternion(0.f, 0.f, std::sqrt(0.5f), std::sqrt(0.5f));
    UpstreamFrame(p, GetParam().Version, this->Metadata());
    const Decoded e = OurParse(Bytes(p));
    double position[3], q[4];
    ASSERT_EQ(wire::DecodePosition(e.Body.Content, e.Body.ContentSize, position, q), wire::Status::Ok) << type;
    EXPECT_NEAR(position[2], 3.0, 1e-6);
    if (type == ::igtl::PositionMessage::POSITION_ONLY) {
      EXPECT_DOUBLE_EQ(q[0], 1.0);  // identity
    } else {
      EXPECT_NEAR(q[0], std::sqrt(0.5), 1e-6);
      EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-6);
    }
    ExpectOurMetadata(e, GetParam());
  }
}

TEST_P(UpstreamToOurs, TrackingDataBothKinds) {
  double m[16];
  TestMatrix(m);
  auto td = ::igtl::TrackingDataMessage::New();
  td->SetDeviceName("Tracker");
  for (const char* name : {"ReferenceToTracker", "PointerToTracker"}) {
    auto e = ::igtl::TrackingDataElement::New();
    e->SetName(name);
    e->SetType(::igtl::TrackingDataElement::TYPE_6D);
    ::igtl::Matrix4x4 mm;
    ToUpstream(m, mm);
    e->SetMatrix(mm);
    td->AddTrackingDataElement(e);
  }
  UpstreamFrame(td, GetParam().Version, this->Metadata());
  const Decoded d = OurParse(Bytes(td));
  int count = 0;
  ASSERT_EQ(wire::CountElements(d.Body.ContentSize, wire::TDataElementSize, count), wire::Status::Ok);
  ASSERT_EQ(count, 2);
  wire::TrackingElement e;
  wire::DecodeTDataElement(d.Body.Content + wire::TDataElementSize, e);
  EXPECT_STREQ(e.Name, "PointerToTracker");
  EXPECT_EQ(e.Type, wire::TrackingType6D);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(e.Matrix[i], m[i], 1e-4) << i;
  ExpectOurMetadata(d, GetParam());

  auto qt = ::igtl::QuaternionTrackingDataMessage::New();
  qt->SetDeviceName("Tracker");
  auto qe = ::igtl::QuaternionTrackingDataElement::New();
  qe->SetName("ProbeToTracker");
  qe->SetPosition(4.f, 5.f, 6.f);
  qe->SetQuaternion(std::sqrt(0.5f), 0.f, 0.f, std::sqrt(0.5f));  // x y z w
  qt->AddQuaternionTrackingDataElement(qe);
  UpstreamFrame(qt, GetParam().Version, this->Metadata());
  const Decoded q = OurParse(Bytes(qt));
  ASSERT_EQ(wire::CountElements(q.Body.ContentSize, wire::QtDataElementSize, count), wire::Status::Ok);
  ASSERT_EQ(count, 1);
  wire::DecodeQtDataElement(q.Body.Content, e);
  EXPECT_STREQ(e.Name, "ProbeToTracker");
  EXPECT_NEAR(e.Position[1], 5.0, 1e-6);
  EXPECT_NEAR(e.Quaternion[0], std::sqrt(0.5), 1e-6);  // w
  EXPECT_NEAR(e.Quaternion[1], std::sqrt(0.5), 1e-6);  // x
}

TEST_P(UpstreamToOurs, StatusStringAndControl) {
  auto st = ::igtl::StatusMessage::New();
  st->SetDeviceName("Device");
  st->SetCode(::igtl::StatusMessage::STATUS_NOT_READY);
  st->SetSubCode(7);
  st->SetErrorName("warming up");
  st->SetStatusString("camera not ready");
  UpstreamFrame(st, GetParam().Version, this->Metadata());
  Decoded d = OurParse(Bytes(st));
  int code = 0;
  char errorName[21];
  ASSERT_EQ(wire::DecodeStatus(d.Body.Content, d.Body.ContentSize, code, errorName), wire::Status::Ok);
  EXPECT_EQ(code, 13);
  EXPECT_STREQ(errorName, "warming up");
  ExpectOurMetadata(d, GetParam());

  auto str = ::igtl::StringMessage::New();
  str->SetDeviceName("Reply");
  str->SetString("Image Guided Therapy");
  UpstreamFrame(str, GetParam().Version, this->Metadata());
  d = OurParse(Bytes(str));
  uint16_t encoding = 0;
  const char* text = nullptr;
  size_t length = 0;
  ASSERT_EQ(wire::DecodeString(d.Body.Content, d.Body.ContentSize, encoding, text, length), wire::Status::Ok);
  EXPECT_EQ(encoding, 3);
  EXPECT_EQ(std::string(text, length), "Image Guided Therapy");

  auto stt = ::igtl::StartTrackingDataMessage::New();
  stt->SetDeviceName("Client");
  stt->SetResolution(20);
  stt->SetCoordinateName("Patient");
  UpstreamFrame(stt, GetParam().Version, this->Metadata());
  d = OurParse(Bytes(stt));
  EXPECT_TRUE(d.Header.Is("STT_TDATA"));
  int32_t resolution = 0;
  char coordinate[33];
  ASSERT_EQ(wire::DecodeStartTracking(d.Body.Content, d.Body.ContentSize, resolution, coordinate), wire::Status::Ok);
  EXPECT_EQ(resolution, 20);
  EXPECT_STREQ(coordinate, "Patient");

  auto sttq = ::igtl::StartQuaternionTrackingDataMessage::New();
  sttq->SetDeviceName("Client");
  sttq->SetResolution(33);
  UpstreamFrame(sttq, GetParam().Version, this->Metadata());
  d = OurParse(Bytes(sttq));
  EXPECT_TRUE(d.Header.Is("STT_QTDATA"));
  ASSERT_EQ(wire::DecodeStartTracking(d.Body.Content, d.Body.ContentSize, resolution, coordinate), wire::Status::Ok);
  EXPECT_EQ(resolution, 33);

  auto rts = ::igtl::RTSQuaternionTrackingDataMessage::New();
  rts->SetDeviceName("Tracker");
  rts->SetStatus(1);
  UpstreamFrame(rts, GetParam().Version, this->Metadata());
  d = OurParse(Bytes(rts));
  int status = -1;
  ASSERT_EQ(wire::DecodeRts(d.Body.Content, d.Body.ContentSize, status), wire::Status::Ok);
  EXPECT_EQ(status, 1);

  for (::igtl::MessageBase::Pointer m : {::igtl::MessageBase::Pointer(::igtl::GetStatusMessage::New().GetPointer()),
                                         ::igtl::MessageBase::Pointer(::igtl::StopTrackingDataMessage::New().GetPointer()),
                                         ::igtl::MessageBase::Pointer(::igtl::StopQuaternionTrackingDataMessage::New().GetPointer())}) {
    m->SetDeviceName("Client");
    UpstreamFrame(m, GetParam().Version, this->Metadata());
    d = OurParse(Bytes(m));
    EXPECT_EQ(d.Body.ContentSize, 0u) << d.Header.Type;
    ExpectOurMetadata(d, GetParam());
  }
}

TEST_P(UpstreamToOurs, Image) {
  // A 3×2×2 int16 volume, LPS, oblique, as a scanner would send it.
  auto image = ::igtl::ImageMessage::New();
  image->SetDeviceName("USProbe");
  image->SetDimensions(3, 2, 2);
  image->SetSpacing(0.5f, 0.75f, 2.f);
  image->SetScalarType(::igtl::ImageMessage::TYPE_INT16);
  image->SetEndian(::igtl::ImageMessage::ENDIAN_LITTLE);
  image->SetCoordinateSystem(::igtl::ImageMessage::COORDINATE_LPS);
  ::igtl::Matrix4x4 mm;
  ::igtl::IdentityMatrix(mm);
  mm[0][0] = 0.f;  // i → -y, j → x (a 90° turn about z), centre at (10, 20, 30) LPS
  mm[1][0] = -1.f;
  mm[0][1] = 1.f;
  mm[1][1] = 0.f;
  mm[0][3] = 10.f;
  mm[1][3] = 20.f;
  mm[2][3] = 30.f;
  image->SetMatrix(mm);
  image->SetHeaderVersion(static_cast<unsigned short>(GetParam().Version));  // before the buffer exists
  image->AllocateScalars();
  int16_t* voxels = static_cast<int16_t*>(image->GetScalarPointer());
  for (int i = 0; i < 12; ++i) voxels[i] = static_cast<int16_t>(-300 + 100 * i);
  UpstreamFrame(image, GetParam().Version, this->Metadata());
  const Decoded d = OurParse(Bytes(image));
  wire::ImageHeader h;
  const uint8_t* pixels = nullptr;
  ASSERT_EQ(wire::DecodeImage(d.Body.Content, d.Body.ContentSize, h, pixels), wire::Status::Ok);
  EXPECT_EQ(h.Size[0], 3);
  EXPECT_EQ(h.Size[2], 2);
  EXPECT_EQ(h.ScalarType, wire::ImageHeader::Int16);
  EXPECT_TRUE(h.IsWholeImage());
  int16_t first;
  std::memcpy(&first, pixels + 2 * 11, 2);  // little endian on this host
  EXPECT_EQ(first, 800);
  // IJK → RAS: column i = 0.5·(0,-1,0) LPS = (0, 0.5, 0) RAS; j = 0.75·(1,0,0) LPS = (-0.75, 0, 0)
  // RAS; k = (0,0,2); first voxel = centre − half extents, then LPS → RAS.
  double m[16];
  h.IjkToRas(m);
  const double expected[16] = {0, -0.75, 0, -(10 - 0.75 * 0.5),
                               0.5, 0, 0, -(20 - (-0.5) * 1.0),
                               0, 0, 2, 30 - 2 * 0.5,
                               0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(m[i], expected[i], 1e-6) << i;
}

INSTANTIATE_TEST_SUITE_P(Framings, UpstreamToOurs,
                         ::testing::Values(Framing{1, false}, Framing{2, false}, Framing{2, true}), Name);

// ---------------------------------------------------------------- sockets, in process

namespace {
using rptest::UpstreamReceive;  // rpUpstreamReceive.h

ToolPose Newest(const IgtlClient& client, const char* name, uint64_t* count = nullptr) {
  return test::Newest(client.Poses(), name, count);
}
IgtlClient::Options ClientOptions(int port) { return test::LoopbackClientOptions(port); }

}  // namespace

// PLUS with a v2 client: v3 framing with TransformStatus metadata, MISSING tools included.
TEST(IgtlUpstreamSocket, OurClientAgainstAPlusLikeV2Server) {
  const int port = test::FreePort();
  auto server = ::igtl::ServerSocket::New();
  ASSERT_EQ(server->CreateServer(port), 0);
  std::atomic<int> requestResolution{-1}, requestVersion{-1}, keepAliveVersion{-1};
  std::atomic<bool> done{false};
  double m[16];
  TestMatrix(m);
  std::thread peer([&] {
    ::igtl::ClientSocket::Pointer socket;
    for (int i = 0; i < 100 && !(socket = server->WaitForConnection(50)); ++i) {
    }
    if (!socket) return;
    socket->SetReceiveTimeout(3000);
    int result = 0;
    auto start = UpstreamReceive<::igtl::StartTrackingDataMessage>(socket, "STT_TDATA", result);
    if (!start || !(result & ::igtl::MessageHeader::UNPACK_BODY)) return;
    requestVersion = start->GetHeaderVersion();
    requestResolution = start->GetResolution();
    auto rts = ::igtl::RTSTrackingDataMessage::New();
    rts->SetDeviceName("Tracker");
    rts->SetStatus(0);
    UpstreamFrame(rts, 2, {});
    socket->Send(rts->GetPackPointer(), rts->GetPackSize());
    for (const auto& [name, status] : {std::make_pair("StylusToTracker", "OK"), std::make_pair("ReferenceToTracker", "MISSING"),
                                       std::make_pair("PointerToTracker", "OUT_OF_VOLUME")}) {
      auto t = ::igtl::TransformMessage::New();
      t->SetDeviceName(name);
      ::igtl::Matrix4x4 mm;
      ToUpstream(m, mm);
      t->SetMatrix(mm);
      UpstreamFrame(t, 2, {{"TransformStatus", status}});
      socket->Send(t->GetPackPointer(), t->GetPackSize());
    }
    auto st = ::igtl::StringMessage::New();
    st->SetDeviceName("CommandReply");
    st->SetString("<CommandReply Status=\"SUCCESS\" />");
    UpstreamFrame(st, 2, {});
    socket->Send(st->GetPackPointer(), st->GetPackSize());
    // Then silence: the client's keep-alive GET_STATUS must arrive in v2 and be answered.
    auto get = UpstreamReceive<::igtl::GetStatusMessage>(socket, "GET_STATUS", result);
    if (get) keepAliveVersion = get->GetHeaderVersion();
    auto status = ::igtl::StatusMessage::New();
    status->SetDeviceName("Tracker");
    status->SetCode(::igtl::StatusMessage::STATUS_OK);
    UpstreamFrame(status, 2, {});
    socket->Send(status->GetPackPointer(), status->GetPackSize());
    while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    socket->CloseSocket();
  });
  auto options = ClientOptions(port);
  options.HeaderVersion = 2;
  options.RequestTrackingData = true;
  options.TrackingIntervalMs = 25;
  options.KeepAliveSeconds = 0.2;
  IgtlClient client(options);
  client.Start();
  EXPECT_TRUE(test::WaitFor([&] { return client.GetStatistics().StatusMessages >= 1; }, 5)) << client.LastError();
  done = true;
  peer.join();
  server->CloseSocket();
  EXPECT_EQ(requestVersion.load(), 2);
  EXPECT_EQ(requestResolution.load(), 25);
  EXPECT_EQ(keepAliveVersion.load(), 2);
  EXPECT_EQ(client.GetStatistics().LastRtsStatus, 0);
  EXPECT_EQ(Newest(client, "StylusToTracker").State, ToolState::OK);
  EXPECT_EQ(Newest(client, "ReferenceToTracker").State, ToolState::Missing);
  EXPECT_EQ(Newest(client, "PointerToTracker").State, ToolState::OutOfVolume);
  double got[16];
  Newest(client, "StylusToTracker").ToMatrix(got);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(got[i], m[i], 1e-4) << i;
  EXPECT_EQ(client.LastString(), "<CommandReply Status=\"SUCCESS\" />");
  const auto s = client.GetStatistics();
  EXPECT_EQ(s.CrcErrors + s.Malformed, 0u);
  client.Stop();
}

// Slicer's OpenIGTLinkIF connector with v2 headers, against `roboplan track --serve`.
TEST(IgtlUpstreamSocket, UpstreamV2ClientAgainstOurServer) {
  ToolPoseTable table;
  const int stylus = table.FindOrAdd("StylusToTracker");
  const int probe = table.FindOrAdd("StylusTipOfTheLongProbeToTracker");  // > 20 characters
  IgtlServer::Options options;
  options.Port = 0;
  IgtlServer server(table, options);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  auto socket = ::igtl::ClientSocket::New();
  ASSERT_EQ(socket->ConnectToServer("127.0.0.1", server.Port()), 0);
  socket->SetReceiveTimeout(3000);
  auto start = ::igtl::StartQuaternionTrackingDataMessage::New();
  start->SetDeviceName("Slicer");
  start->SetResolution(20);
  UpstreamFrame(start, 2, {});
  ASSERT_TRUE(socket->Send(start->GetPackPointer(), start->GetPackSize()));
  int result = 0;
  auto rts = UpstreamReceive<::igtl::RTSQuaternionTrackingDataMessage>(socket, "RTS_QTDATA", result);
  ASSERT_TRUE(rts);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_EQ(rts->GetHeaderVersion(), 2);
  EXPECT_EQ(rts->GetStatus(), 0);

  double m[16];
  TestMatrix(m);
  ToolPose pose;
  pose.FromMatrix(m);
  pose.State = ToolState::OK;
  table.Publish(probe, pose);
  ToolPose missing;
  missing.State = ToolState::Missing;
  table.Publish(stylus, missing);

  bool sawProbe = false, sawMissing = false;
  for (int i = 0; i < 4 && !(sawProbe && sawMissing); ++i) {
    auto transform = UpstreamReceive<::igtl::TransformMessage>(socket, "TRANSFORM", result);
    ASSERT_TRUE(transform);
    ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY) << "upstream refused our TRANSFORM";
    EXPECT_EQ(transform->GetHeaderVersion(), 2);
    std::string status, fullName;
    ASSERT_TRUE(transform->GetMetaDataElement("TransformStatus", status));
    if (transform->GetMetaDataElement("IGTL_DEVICE_NAME", fullName)) {
      EXPECT_EQ(fullName, "StylusTipOfTheLongProbeToTracker");
      EXPECT_EQ(std::string(transform->GetDeviceName()), fullName.substr(0, 20));
      EXPECT_EQ(status, "OK");
      ::igtl::Matrix4x4 got;
      transform->GetMatrix(got);
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[r][k], m[4 * r + k], 1e-4);
      sawProbe = true;
    } else {
      EXPECT_STREQ(transform->GetDeviceName(), "StylusToTracker");
      EXPECT_EQ(status, "MISSING");  // v2 peers get missing tools, with their status
      sawMissing = true;
    }
  }
  EXPECT_TRUE(sawProbe && sawMissing);
  auto qtdata = UpstreamReceive<::igtl::QuaternionTrackingDataMessage>(socket, "QTDATA", result);
  ASSERT_TRUE(qtdata);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  ASSERT_EQ(qtdata->GetNumberOfQuaternionTrackingDataElements(), 1);  // only the valid tool
  ::igtl::QuaternionTrackingDataElement::Pointer e;
  qtdata->GetQuaternionTrackingDataElement(0, e);
  float position[3];
  e->GetPosition(position);
  EXPECT_NEAR(position[2], m[11], 1e-3);

  auto get = ::igtl::GetStatusMessage::New();
  get->SetDeviceName("Slicer");
  UpstreamFrame(get, 2, {});
  ASSERT_TRUE(socket->Send(get->GetPackPointer(), get->GetPackSize()));
  auto status = UpstreamReceive<::igtl::StatusMessage>(socket, "STATUS", result);
  ASSERT_TRUE(status);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_EQ(status->GetCode(), ::igtl::StatusMessage::STATUS_OK);
  socket->CloseSocket();
  server.Stop();
}

// ---------------------------------------------------------------- sockets, upstream's programs

namespace {
// Starts an upstream example server on a free port and waits until it listens.
bool StartServer(test::ChildProcess& child, std::vector<std::string> arguments, const std::string& log, int& port) {
  port = test::FreePort();
  arguments.insert(arguments.begin() + 1, std::to_string(port));
  std::string error;
  if (!child.Start(arguments, OutputDir() + "/" + log, error)) {
    ADD_FAILURE() << error;
    return false;
  }
  return test::WaitFor([&] { return !child.Running() || test::PortListening(port); }, 10) && child.Running();
}

// AddressSanitizer or UBSan in the upstream program (built with the project's sanitizer) on our bytes.
void ExpectNoSanitizerReport(const std::string& output) {
  EXPECT_EQ(output.find("ERROR: AddressSanitizer"), std::string::npos) << output.substr(0, 4000);
  EXPECT_EQ(output.find("runtime error:"), std::string::npos) << output.substr(0, 4000);
}
}  // namespace

TEST(IgtlUpstreamPrograms, TrackerServerToOurClient) {
  test::ChildProcess peer;
  int port = 0;
  ASSERT_TRUE(StartServer(peer, {Program("TrackerServer"), "50"}, "TrackerServer.log", port));
  IgtlClient client(ClientOptions(port));
  client.Start();
  ASSERT_TRUE(test::WaitFor([&] { return client.GetStatistics().Poses >= 15; }, 10)) << client.LastError();
  const ToolPose pose = Newest(client, "Tracker");
  const auto printed = test::PrintedMatrices(peer.Output());  // printed before each send
  client.Stop();
  peer.Kill();
  ASSERT_FALSE(printed.empty());
  // The received pose is one that TrackerServer sent: same translation, and the rotation we
  // re-orthonormalise from the same 3×3 (TrackerServer's quaternions are not unit).
  const std::array<double, 16>* match = nullptr;
  for (const auto& m : printed)
    if (std::abs(m[3] - pose.Translation[0]) < 1e-3 && std::abs(m[7] - pose.Translation[1]) < 1e-3 &&
        std::abs(m[11] - pose.Translation[2]) < 1e-3)
      match = &m;
  ASSERT_NE(match, nullptr) << "our pose " << pose.Translation[0] << " " << pose.Translation[1] << " " << pose.Translation[2];
  ToolPose expected;
  expected.FromMatrix(match->data());
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(std::abs(pose.Quaternion[k]), std::abs(expected.Quaternion[k]), 1e-3);
  const auto s = client.GetStatistics();
  EXPECT_EQ(s.CrcErrors + s.Malformed, 0u);
  EXPECT_EQ(pose.State, ToolState::OK);
  ExpectNoSanitizerReport(peer.Output());
}

TEST(IgtlUpstreamPrograms, TrackingDataServersToOurClient) {
  for (const bool quaternion : {false, true}) {
    SCOPED_TRACE(quaternion ? "QuaternionTrackingDataServer" : "TrackingDataServer");
    test::ChildProcess peer;
    int port = 0;
    ASSERT_TRUE(StartServer(peer, {Program(quaternion ? "QuaternionTrackingDataServer" : "TrackingDataServer")},
                            quaternion ? "QuaternionTrackingDataServer.log" : "TrackingDataServer.log", port));
    auto options = ClientOptions(port);
    options.RequestTrackingData = !quaternion;
    options.RequestQuaternionData = quaternion;
    options.TrackingIntervalMs = 20;
    IgtlClient client(options);
    client.Start();
    ASSERT_TRUE(test::WaitFor([&] { return client.GetStatistics().Poses >= 30; }, 10)) << client.LastError();
    client.Stop();  // sends STP_*
    for (const char* channel : {"Channel 0", "Channel 1", "Channel 2"}) {
      // The server's positions: 50·(cos φ, sin φ, cos φ).
      const ToolPose p = Newest(client, channel);
      EXPECT_NEAR(p.Translation[0], p.Translation[2], 1e-4) << channel;
      EXPECT_NEAR(std::hypot(p.Translation[0], p.Translation[1]), 50.0, 1e-3) << channel;
      if (quaternion) {  // (0, ⅔cos θ, 0.57735, ⅔sin θ) normalised
        EXPECT_NEAR(p.Quaternion[1], 0.0, 1e-6);
        EXPECT_NEAR(std::abs(p.Quaternion[3]), 0.577350269 / std::sqrt(4.0 / 9 + 1.0 / 3), 1e-5);
      }
    }
    EXPECT_EQ(client.GetStatistics().LastRtsStatus, -1);  // these servers send no RTS
    const auto s = client.GetStatistics();
    EXPECT_EQ(s.CrcErrors + s.Malformed, 0u);
    EXPECT_TRUE(test::WaitFor([&] { return peer.Output().find("STP_") != std::string::npos; }, 3))
        << "the server did not see our STP_ message:\n" << peer.Output();
    peer.Kill();
    EXPECT_NE(peer.Output().find(quaternion ? "Received a STT_QTDATA message." : "Received a STT_TDATA message."),
              std::string::npos);
    ExpectNoSanitizerReport(peer.Output());
  }
}

TEST(IgtlUpstreamPrograms, StatusAndStringServersToOurClient) {
  {
    test::ChildProcess peer;
    int port = 0;
    ASSERT_TRUE(StartServer(peer, {Program("StatusServer")}, "StatusServer.log", port));
    IgtlClient client(ClientOptions(port));
    client.Start();
    ASSERT_TRUE(test::WaitFor([&] { return client.GetStatistics().StatusMessages >= 1; }, 5)) << client.LastError();
    EXPECT_EQ(client.GetStatistics().LastStatusCode, 1);
    EXPECT_EQ(client.GetStatistics().Malformed, 0u);
    client.Stop();
    peer.Kill();
    ExpectNoSanitizerReport(peer.Output());
  }
  {
    test::ChildProcess peer;
    int port = 0;
    ASSERT_TRUE(StartServer(peer, {Program("StringServer"), "50"}, "StringServer.log", port));
    IgtlClient client(ClientOptions(port));
    client.Start();
    ASSERT_TRUE(test::WaitFor([&] { return client.GetStatistics().StringMessages >= 3; }, 5)) << client.LastError();
    const std::string last = client.LastString();
    client.Stop();
    peer.Kill();
    EXPECT_NE(peer.Output().find("Sending string: " + last), std::string::npos) << last;
    EXPECT_EQ(client.GetStatistics().Malformed + client.GetStatistics().CrcErrors, 0u);
    ExpectNoSanitizerReport(peer.Output());
  }
}

// A scanner streaming images (PLUS's tracked ultrasound, a live slice): each IMAGE becomes the
// volume node named after the device, geometry from the message, voxels as sent.
TEST(IgtlUpstreamPrograms, ImagerServerIntoAVolumeNode) {
  const std::string images = std::string(ROBOPLAN_UPSTREAM_IGTL_SOURCE) + "/Examples/Imager/img";
  test::ChildProcess peer;
  int port = 0;
  ASSERT_TRUE(StartServer(peer, {Program("ImagerServer"), "20", images}, "ImagerServer.log", port));
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  std::string error;
  const int id = logic->AddSource(std::make_unique<IgtlClient>(ClientOptions(port)), error);
  ASSERT_GE(id, 0) << error;
  std::vector<vtkRPTrackingLogic::ImageStatistics> stats;
  ASSERT_TRUE(test::WaitFor([&] {
    logic->UpdateNodes(SteadySeconds());
    stats = logic->GetImageStatistics();
    return !stats.empty() && stats[0].Shown >= 3;
  }, 10)) << logic->GetSource(id)->StatusText();
  auto* node = vtkRPScalarVolumeNode::SafeDownCast(scene->GetFirstNodeByName("ImagerClient"));  // the device name
  ASSERT_NE(node, nullptr);
  EXPECT_EQ(scene->GetNodesByClass("vtkRPScalarVolumeNode").size(), 1u);  // updated in place, not one per frame
  vtkImageData* image = node->GetImageData();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 256);
  EXPECT_EQ(dims[1], 256);
  EXPECT_EQ(dims[2], 1);
  EXPECT_EQ(image->GetScalarType(), VTK_UNSIGNED_CHAR);
  // ImagerServer: spacing (1, 1, 5), directions diag(1, -1, 1), centre (0, 0, 0) in RAS: the first
  // voxel is half the extent away from the centre.
  const double expected[16] = {1, 0, 0, -127.5, 0, -1, 0, 127.5, 0, 0, 5, 0, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(node->GetIJKToRASMatrix()->GetElement(i / 4, i % 4), expected[i], 1e-6) << i;
  // The voxels are one of the files the server read, byte for byte.
  const auto* voxels = static_cast<const uint8_t*>(image->GetScalarPointer());
  int matches = 0;
  for (int k = 1; k <= 5; ++k) {
    std::ifstream f(images + "/igtlTestImage" + std::to_string(k) + ".raw", std::ios::binary);
    const std::vector<uint8_t> raw((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    ASSERT_EQ(raw.size(), 65536u);
    if (std::equal(raw.begin(), raw.end(), voxels)) ++matches;
  }
  EXPECT_EQ(matches, 1);
  EXPECT_GT(node->GetWindow(), 0);
  logic->RemoveSource(id);
  peer.Kill();
  ExpectNoSanitizerReport(peer.Output());
}

namespace {
// Our server streaming one tool with a known pose (republished so that it stays fresh).
struct ServedTool {
  ServedTool() {
    TestMatrix(Matrix);
    Pose.FromMatrix(Matrix);
    Pose.State = ToolState::OK;
    Slot = Table.FindOrAdd("StylusToTracker");
    Table.Publish(Slot, Pose);
    IgtlServer::Options o;
    o.Port = 0;
    o.SendHz = 30;
    Server = std::make_unique<IgtlServer>(Table, o);
    std::string error;
    EXPECT_TRUE(Server->Start(error)) << error;
    Publisher = std::thread([this] {
      while (!Stop) {
        Table.Publish(Slot, Pose);
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
      }
    });
  }
  ~ServedTool() {
    Stop = true;
    Publisher.join();
    Server->Stop();
  }
  double Matrix[16];
  ToolPose Pose;
  ToolPoseTable Table;
  int Slot = 0;
  std::unique_ptr<IgtlServer> Server;
  std::atomic<bool> Stop{false};
  std::thread Publisher;
};

void ExpectSameMatrix(const std::array<double, 16>& printed, const double m[16]) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(printed[4 * r + k], m[4 * r + k], 1e-3) << r << "," << k;
}
}  // namespace

TEST(IgtlUpstreamPrograms, OurServerToReceiveClient) {
  ServedTool served;
  test::ChildProcess peer;
  std::string error;
  ASSERT_TRUE(peer.Start({Program("ReceiveClient"), "127.0.0.1", std::to_string(served.Server->Port())},
                         OutputDir() + "/ReceiveClient.log", error)) << error;
  EXPECT_TRUE(test::WaitFor([&] { return test::Count(peer.Output(), "Receiving TRANSFORM data type.") >= 5; }, 10))
      << peer.Output();
  served.Stop = true;  // nothing fresh: the server's STATUS keep-alives follow
  EXPECT_TRUE(test::WaitFor([&] { return peer.Output().find(" Code      : 1") != std::string::npos; }, 5)) << peer.Output();
  peer.Kill();
  const std::string output = peer.Output();
  EXPECT_NE(output.find("Name: StylusToTracker"), std::string::npos);
  const auto printed = test::PrintedMatrices(output);  // only when upstream's CRC check passed
  ASSERT_GE(printed.size(), 5u);
  for (const auto& m : printed) ExpectSameMatrix(m, served.Matrix);
  ExpectNoSanitizerReport(output);
}

TEST(IgtlUpstreamPrograms, OurServerToTrackingDataClients) {
  for (const bool quaternion : {false, true}) {
    SCOPED_TRACE(quaternion ? "QuaternionTrackingDataClient" : "TrackingDataClient");
    ServedTool served;
    test::ChildProcess peer;
    std::string error;
    ASSERT_TRUE(peer.Start({Program(quaternion ? "QuaternionTrackingDataClient" : "TrackingDataClient"), "127.0.0.1",
                            std::to_string(served.Server->Port()), "50"},
                           OutputDir() + (quaternion ? "/QuaternionTrackingDataClient.log" : "/TrackingDataClient.log"),
                           error)) << error;
    // RTS_* answers the client's STT_*; after 10 messages it sends STP_*, answered by a second RTS_*.
    EXPECT_TRUE(test::WaitFor([&] { return test::Count(peer.Output(), "Receiving : RTS_") >= 2; }, 10)) << peer.Output();
    peer.Kill();
    const std::string output = peer.Output();
    // The client counts every message (our TRANSFORMs too) towards its 10.
    EXPECT_GE(test::Count(output, " Name       : StylusToTracker"), 3u) << output;
    if (quaternion) {
      // Position and quaternion (x y z w) printed by the client.
      const size_t at = output.find(" Position   : ");
      ASSERT_NE(at, std::string::npos);
      double x, y, z;
      char c;
      std::istringstream(output.substr(at + 14)) >> x >> c >> y >> c >> z;
      EXPECT_NEAR(x, served.Matrix[3], 1e-3);
      EXPECT_NEAR(z, served.Matrix[11], 1e-2);
      const size_t q = output.find(" Quaternion : ");
      ASSERT_NE(q, std::string::npos);
      double qx, qy, qz, qw;
      std::istringstream(output.substr(q + 14)) >> qx >> c >> qy >> c >> qz >> c >> qw;
      EXPECT_NEAR(qx, served.Pose.Quaternion[1], 1e-4);
      EXPECT_NEAR(qw, served.Pose.Quaternion[0], 1e-4);
    } else {
      const auto printed = test::PrintedMatrices(output);
      ASSERT_GE(printed.size(), 3u);
      for (const auto& m : printed) ExpectSameMatrix(m, served.Matrix);
    }
    ExpectNoSanitizerReport(output);
  }
}

// PlusServer's commands as Slicer's OpenIGTLinkRemote sends them, on upstream's own classes: a
// first STATUS (v2 headers), a COMMAND with MRMLNodeName metadata answered by RTS_COMMAND with
// Status/Message metadata, and the older STRING CMD_<uid> answered by STRING ACK_<uid>.
TEST(IgtlUpstreamSocket, SlicerLikeClientSendsPlusCommandsAndDecodesTheRepliesUpstream) {
  ToolPoseTable table;
  table.FindOrAdd("StylusToTracker");
  IgtlServer::Options options;
  options.Port = 0;
  options.DeviceIds = {"TrackerDevice", "CaptureDevice"};
  IgtlServer server(table, options);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  auto socket = ::igtl::ClientSocket::New();
  ASSERT_EQ(socket->ConnectToServer("127.0.0.1", server.Port()), 0);
  socket->SetReceiveTimeout(3000);
  auto status = ::igtl::StatusMessage::New();
  status->SetCode(::igtl::StatusMessage::STATUS_OK);
  UpstreamFrame(status, 2, {});
  ASSERT_TRUE(socket->Send(status->GetPackPointer(), status->GetPackSize()));

  auto command = ::igtl::CommandMessage::New();
  command->SetDeviceName("OpenIGTLinkRemote");
  command->SetCommandId(17);
  command->SetCommandName("RequestDeviceIds");
  command->SetCommandContent("<Command Name=\"RequestDeviceIds\" />");
  UpstreamFrame(command, 2, {{"MRMLNodeName", "RequestDeviceIds"}});
  ASSERT_TRUE(socket->Send(command->GetPackPointer(), command->GetPackSize()));
  int result = 0;
  auto rts = UpstreamReceive<::igtl::RTSCommandMessage>(socket, "RTS_COMMAND", result);
  ASSERT_TRUE(rts);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY) << "upstream refused our RTS_COMMAND";
  EXPECT_EQ(rts->GetCommandId(), 17u);
  EXPECT_EQ(rts->GetCommandName(), "RequestDeviceIds");
  EXPECT_EQ(rts->GetCommandContent(), "<CommandReply Status=\"SUCCESS\" Message=\"TrackerDevice,CaptureDevice\" />");
  std::string value;
  ASSERT_TRUE(rts->GetMetaDataElement("Status", value));
  EXPECT_EQ(value, "SUCCESS");
  ASSERT_TRUE(rts->GetMetaDataElement("Message", value));
  EXPECT_EQ(value, "TrackerDevice,CaptureDevice");

  auto string = ::igtl::StringMessage::New();
  string->SetDeviceName("CMD_5");
  string->SetString("<Command Name=\"RequestChannelIds\" />");
  UpstreamFrame(string, 2, {{"MRMLNodeName", "CMD_5"}});
  ASSERT_TRUE(socket->Send(string->GetPackPointer(), string->GetPackSize()));
  auto ack = UpstreamReceive<::igtl::StringMessage>(socket, "STRING", result);
  ASSERT_TRUE(ack);
  ASSERT_TRUE(result & ::igtl::MessageHeader::UNPACK_BODY);
  EXPECT_STREQ(ack->GetDeviceName(), "ACK_5");
  EXPECT_STREQ(ack->GetString(), "<CommandReply Status=\"SUCCESS\" Message=\"TrackerStream\" />");
  socket->CloseSocket();
}

namespace {
// An upstream COMMAND from a Slicer-like client; the RTS_COMMAND's Message (Status in `ok`).
std::string UpstreamCommand(::igtl::ClientSocket* socket, unsigned id, const std::string& xml, bool& ok) {
  auto command = ::igtl::CommandMessage::New();
  command->SetDeviceName("OpenIGTLinkRemote");
  command->SetCommandId(id);
  command->SetCommandName("Command");
  command->SetCommandContent(xml);
  UpstreamFrame(command, 2, {});
  ok = false;
  if (!socket->Send(command->GetPackPointer(), command->GetPackSize())) return "";
  int result = 0;
  auto rts = UpstreamReceive<::igtl::RTSCommandMessage>(socket, "RTS_COMMAND", result, 2000);
  std::string status, message;
  if (!rts || !rts->GetMetaDataElement("Status", status) || !rts->GetMetaDataElement("Message", message)) return "";
  ok = status == "SUCCESS";
  return message;
}

// The next StylusTipToReference TRANSFORM's status and z translation (and matrix); "" when none came.
std::string NextTipStatus(::igtl::ClientSocket* socket, double& z, ::igtl::Matrix4x4* matrix = nullptr) {
  int result = 0;
  for (int i = 0; i < 400; ++i) {
    auto t = UpstreamReceive<::igtl::TransformMessage>(socket, "TRANSFORM", result);
    if (!t) return "";
    if (std::string(t->GetDeviceName()) != "StylusTipToReference") continue;
    std::string status;
    t->GetMetaDataElement("TransformStatus", status);
    ::igtl::Matrix4x4 m;
    t->GetMatrix(m);
    z = m[2][3];
    if (matrix) std::memcpy(*matrix, m, sizeof m);
    return status;
  }
  return "";
}
}  // namespace

// `roboplan track --plus-config` as PlusServer: a simulated Vega over TCP, the configuration's
// transform repository behind the served StylusTipToReference and the GetTransform and
// UpdateTransform commands; an upstream client sees OK, then MISSING when the tool is hidden.
TEST(IgtlUpstreamSocket, PlusConfigurationServesTheRepositoryStatusAndCommandsActOnIt) {
  const std::string config = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data/ConfigFiles/PlusDeviceSet_Server_NDIVega.xml";
  RP_REQUIRE_SHARED_DATA(config);
  PolarisSimulator::Options so;
  so.TcpPort = 0;
  PolarisSimulator vega(so);
  std::string error;
  ASSERT_TRUE(vega.Start(error)) << error;
  const int port = test::FreePort();
  std::ostringstream out, err;
  int code = -1;
  std::thread track([&] {
    code = RunTrackCommand({"--plus-config", config, "--ndi-tcp", vega.PortPath(), "--seconds", "4", "--serve",
                            std::to_string(port)},
                           nullptr, out, err);
  });
  auto socket = ::igtl::ClientSocket::New();
  bool connected = false;
  for (int i = 0; i < 300 && !connected; ++i) {
    connected = socket->ConnectToServer("127.0.0.1", port) == 0;
    if (!connected) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(connected);
  socket->SetReceiveTimeout(3000);
  auto hello = ::igtl::StatusMessage::New();  // Slicer's first STATUS: v2 headers from now on
  hello->SetCode(::igtl::StatusMessage::STATUS_OK);
  UpstreamFrame(hello, 2, {});
  ASSERT_TRUE(socket->Send(hello->GetPackPointer(), hello->GetPackSize()));

  double z = 0;
  std::string status;
  ::igtl::Matrix4x4 served;
  for (int i = 0; i < 100 && status != "OK"; ++i) status = NextTipStatus(socket, z, &served);
  ASSERT_EQ(status, "OK");
  EXPECT_NEAR(z, -1500.0 - 88.5321, 1e-3);  // the tool at z = -1500, the tip 88.53 mm along -z

  // GetTransform of a chain the server does not stream (the inverse): computed by the repository.
  bool ok = false;
  std::string reply = UpstreamCommand(socket, 1, "<Command Name=\"GetTransform\" TransformName=\"ReferenceToStylusTip\" />", ok);
  EXPECT_TRUE(ok) << reply;
  std::istringstream numbers(reply);
  double m[16] = {};
  for (double& v : m) numbers >> v;
  for (int r = 0; r < 3; ++r) {  // served · reply = identity (the still tool: noise only)
    for (int k = 0; k < 4; ++k) {
      double product = 0;
      for (int j = 0; j < 4; ++j) product += served[r][j] * m[4 * j + k];
      EXPECT_NEAR(product, r == k ? 1.0 : 0.0, k == 3 ? 0.2 : 1e-3) << reply;
    }
  }
  UpstreamCommand(socket, 5, "<Command Name=\"GetTransform\" TransformName=\"StylusTipToNowhere\" />", ok);
  EXPECT_FALSE(ok);  // frames the repository does not connect
  // UpdateTransform of the fixed StylusTipToStylus: the repository's answer and the stream move.
  reply = UpstreamCommand(socket, 2,
                          "<Command Name=\"UpdateTransform\" TransformName=\"StylusTipToStylus\" "
                          "TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 -100 0 0 0 1\" />",
                          ok);
  EXPECT_TRUE(ok) << reply;
  for (int i = 0; i < 100 && std::abs(z - (-1600.0)) > 0.5; ++i) status = NextTipStatus(socket, z);
  EXPECT_NEAR(z, -1600.0, 0.5);
  // A computed transform cannot be set, as in PLUS; a tracker's transform neither.
  UpstreamCommand(socket, 3,
                  "<Command Name=\"UpdateTransform\" TransformName=\"StylusTipToReference\" "
                  "TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\" />",
                  ok);
  EXPECT_FALSE(ok);
  UpstreamCommand(socket, 6,
                  "<Command Name=\"UpdateTransform\" TransformName=\"StylusToReference\" "
                  "TransformValue=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\" />",
                  ok);
  EXPECT_FALSE(ok);  // the tracker's

  // The tool out of view: MISSING, with TransformStatus, to this v2 client.
  ASSERT_EQ(vega.ToolNames().size(), 1u);
  vega.SetOccluded(vega.ToolNames()[0], true);
  for (int i = 0; i < 200 && status != "MISSING"; ++i) status = NextTipStatus(socket, z);
  EXPECT_EQ(status, "MISSING");
  reply = UpstreamCommand(socket, 4, "<Command Name=\"GetTransform\" TransformName=\"ReferenceToStylusTip\" />", ok);
  EXPECT_TRUE(ok) << reply;  // connected, with its last matrix, as PLUS answers
  vega.SetOccluded(vega.ToolNames()[0], false);
  for (int i = 0; i < 200 && status != "OK"; ++i) status = NextTipStatus(socket, z);
  EXPECT_EQ(status, "OK");
  socket->CloseSocket();
  track.join();
  EXPECT_EQ(code, 0) << err.str();
}

namespace {
// PLUS's igtlPlusClientInfoMessage: a STRING body (the <ClientInfo> XML) sent as CLIENTINFO.
class UpstreamClientInfoMessage : public ::igtl::StringMessage {
 public:
  using Pointer = ::igtl::SmartPointer<UpstreamClientInfoMessage>;
  static Pointer New() {
    Pointer message = new UpstreamClientInfoMessage;
    message->UnRegister();
    return message;
  }

 protected:
  UpstreamClientInfoMessage() { this->m_SendMessageType = "CLIENTINFO"; }
};
}  // namespace

// PlusServer's CLIENTINFO: the client names one served transform and one the server does not
// stream (computed by the transform provider); it then gets those two and no other, while a
// second client without CLIENTINFO still gets every served transform.
TEST(IgtlUpstreamSocket, ClientInfoReplacesTheDefaultForThatClientOnly) {
  ToolPoseTable table;
  const int stylus = table.FindOrAdd("StylusToTracker");
  const int reference = table.FindOrAdd("ReferenceToTracker");
  IgtlServer::Options options;
  options.Port = 0;
  options.Transforms = [&](const std::string& from, const std::string& to, double m[16], ToolState& state) {
    if (from != "Stylus" || to != "Reference") return false;  // StylusToReference: x 100 - 40
    ToolPose a, b;
    table.Read(stylus, a);
    table.Read(reference, b);
    for (int i = 0; i < 16; ++i) m[i] = (i % 5 == 0) ? 1.0 : 0.0;
    m[3] = a.Translation[0] - b.Translation[0];
    state = ToolState::OK;
    return true;
  };
  IgtlServer server(table, options);
  std::string error;
  ASSERT_TRUE(server.Start(error)) << error;
  auto filtered = ::igtl::ClientSocket::New(), plain = ::igtl::ClientSocket::New();
  ASSERT_EQ(filtered->ConnectToServer("127.0.0.1", server.Port()), 0);
  ASSERT_EQ(plain->ConnectToServer("127.0.0.1", server.Port()), 0);
  filtered->SetReceiveTimeout(3000);
  plain->SetReceiveTimeout(3000);
  auto info = UpstreamClientInfoMessage::New();
  info->SetDeviceName("Slicer");
  info->SetString("<ClientInfo><MessageTypes><Message Type=\"TRANSFORM\" /></MessageTypes>"
                  "<TransformNames><Transform Name=\"ReferenceToTracker\" /><Transform From=\"Stylus\" To=\"Reference\" />"
                  "</TransformNames></ClientInfo>");
  UpstreamFrame(info, 2, {});
  ASSERT_TRUE(filtered->Send(info->GetPackPointer(), info->GetPackSize()));
  // Until the server has read the CLIENTINFO (it sends nothing back), poses go to both: wait for
  // a GET_STATUS answer, which it handles after the CLIENTINFO sent before it.
  auto get = ::igtl::GetStatusMessage::New();
  get->SetDeviceName("Slicer");
  UpstreamFrame(get, 2, {});
  ASSERT_TRUE(filtered->Send(get->GetPackPointer(), get->GetPackSize()));
  int result = 0;
  ASSERT_TRUE(UpstreamReceive<::igtl::StatusMessage>(filtered, "STATUS", result));

  std::map<std::string, int> got, plainGot;
  for (int round = 0; round < 5; ++round) {
    ToolPose pose;
    pose.State = ToolState::OK;
    pose.Translation[0] = 100;
    table.Publish(stylus, pose);
    pose.Translation[0] = 40;
    table.Publish(reference, pose);
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
  for (int i = 0; i < 10; ++i) {
    auto t = UpstreamReceive<::igtl::TransformMessage>(filtered, "TRANSFORM", result, 5);
    if (!t) break;
    ++got[t->GetDeviceName()];
    if (std::string(t->GetDeviceName()) == "StylusToReference") {
      ::igtl::Matrix4x4 m;
      t->GetMatrix(m);
      EXPECT_NEAR(m[0][3], 60.0, 1e-4);
    }
    if (got.size() == 2 && got["ReferenceToTracker"] >= 2 && got["StylusToReference"] >= 2) break;
  }
  for (int i = 0; i < 6; ++i) {
    auto t = UpstreamReceive<::igtl::TransformMessage>(plain, "TRANSFORM", result, 5);
    if (t) ++plainGot[t->GetDeviceName()];
  }
  EXPECT_EQ(got.count("StylusToTracker"), 0u);  // served, but not named by this client
  EXPECT_GE(got["ReferenceToTracker"], 1);
  EXPECT_GE(got["StylusToReference"], 1);
  EXPECT_GE(plainGot["StylusToTracker"], 1);  // the other client keeps the default
  EXPECT_GE(plainGot["ReferenceToTracker"], 1);
  EXPECT_EQ(plainGot.count("StylusToReference"), 0u);
  filtered->CloseSocket();
  plain->CloseSocket();
  server.Stop();
}

#endif  // ROBOPLAN_UPSTREAM_IGTL
