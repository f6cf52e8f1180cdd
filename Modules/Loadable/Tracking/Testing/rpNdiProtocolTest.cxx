// NDI Combined API framing and parsers on byte sequences (vectors from the protocol notes).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "rpNdiProtocol.h"
#include "rpToolDefinition.h"

using namespace rp;

namespace {
uint16_t Crc(const std::string& s) { return ndi::Crc16(s.data(), s.size()); }

std::string WithCrc(const std::string& payload) {
  char crc[4];
  ndi::WriteHex(crc, Crc(payload), 4);
  return payload + std::string(crc, 4) + "\r";
}

const uint8_t* Bytes(const std::string& s) { return reinterpret_cast<const uint8_t*>(s.data()); }

void PutF32(std::vector<uint8_t>& b, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(bits >> (8 * i)));
}
void PutU32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
std::vector<uint8_t> BxFrame(const std::vector<uint8_t>& body) {
  std::vector<uint8_t> f = {0xC4, 0xA5, static_cast<uint8_t>(body.size() & 0xFF), static_cast<uint8_t>(body.size() >> 8)};
  const uint16_t h = ndi::Crc16(f.data(), 4);
  f.push_back(static_cast<uint8_t>(h));
  f.push_back(static_cast<uint8_t>(h >> 8));
  f.insert(f.end(), body.begin(), body.end());
  const uint16_t c = ndi::Crc16(body.data(), body.size());
  f.push_back(static_cast<uint8_t>(c));
  f.push_back(static_cast<uint8_t>(c >> 8));
  return f;
}
// Two valid handles, one missing, one disabled.
std::vector<uint8_t> SampleBxBody() {
  std::vector<uint8_t> b = {4};
  b.push_back(0x0A);
  b.push_back(0x01);
  for (float v : {0.5f, 0.5f, -0.5f, 0.5f, 10.25f, -20.5f, -1500.75f, 0.125f}) PutF32(b, v);
  PutU32(b, 0x31);
  PutU32(b, 1234);
  b.push_back(0x0B);
  b.push_back(0x01);
  for (float v : {1.f, 0.f, 0.f, 0.f, 1.f, 2.f, 3.f, 0.25f}) PutF32(b, v);
  PutU32(b, 0x71);  // out of volume
  PutU32(b, 1234);
  b.push_back(0x0C);
  b.push_back(0x02);
  PutU32(b, 0x31);
  PutU32(b, 1234);
  b.push_back(0x0D);
  b.push_back(0x04);
  b.push_back(0x00);
  b.push_back(0x00);
  return b;
}
}  // namespace

TEST(NdiCrc, VectorsFromTheNotes) {
  EXPECT_EQ(Crc("123456789"), 0xBB3D);
  EXPECT_EQ(Crc("INIT:"), 0xE3A5);
  EXPECT_EQ(Crc("RESET"), 0xBE6F);
  EXPECT_EQ(Crc("OKAY"), 0xA896);
  EXPECT_EQ(Crc("VER:0"), 0x65EE);
  EXPECT_EQ(Crc("TX:0001"), 0x031A);
  EXPECT_EQ(Crc("BX:0801"), 0x00EC);
  EXPECT_EQ(Crc("PHRQ:*********1****"), 0xA4C1);
  EXPECT_EQ(Crc("COMM:50000"), 0x0048);
}

TEST(NdiFraming, Commands) {
  char out[64];
  size_t n = ndi::FormatCommand(out, sizeof out, "INIT", "");
  EXPECT_EQ(std::string(out, n), "INIT:E3A5\r");
  n = ndi::FormatCommand(out, sizeof out, "BX", "0801");
  EXPECT_EQ(std::string(out, n), "BX:080100EC\r");
  n = ndi::FormatCommand(out, sizeof out, "RESET", nullptr, false);
  EXPECT_EQ(std::string(out, n), "RESET\r");
  n = ndi::FormatCommand(out, sizeof out, "VER", "0", false);
  EXPECT_EQ(std::string(out, n), "VER 0\r");
  EXPECT_EQ(ndi::FormatCommand(out, 8, "PHRQ", "*********1****"), 0u);  // does not fit
}

TEST(NdiFraming, AsciiRepliesAndErrors) {
  const std::string okay = "OKAYA896\r";
  const char* payload;
  size_t length;
  ASSERT_TRUE(ndi::CheckAsciiReply(Bytes(okay), okay.size(), payload, length).Ok());
  EXPECT_EQ(std::string(payload, length), "OKAY");
  const std::string reset = "RESETBE6F\r";
  ASSERT_TRUE(ndi::CheckAsciiReply(Bytes(reset), reset.size(), payload, length).Ok());

  const std::string bad = "OKAYA897\r";
  EXPECT_EQ(ndi::CheckAsciiReply(Bytes(bad), bad.size(), payload, length).Code, ndi::ParseCode::BadCrc);
  const std::string error = WithCrc("ERROR0C");
  const ndi::ParseResult r = ndi::CheckAsciiReply(Bytes(error), error.size(), payload, length);
  EXPECT_EQ(r.Code, ndi::ParseCode::DeviceError);
  EXPECT_EQ(r.DeviceError, 0x0C);
  EXPECT_STREQ(ndi::ErrorCodeText(0x0C), "command invalid in current operating mode");
  EXPECT_EQ(ndi::CheckAsciiReply(Bytes(okay), 3, payload, length).Code, ndi::ParseCode::Truncated);
}

TEST(NdiTx, ExampleFromTheNotes) {
  const std::string reply = "0101+10000+00000+00000+00000+001000-002050-150025+01234000000310000001A\n0000F59A\r";
  ndi::TrackingReply tx;
  const ndi::ParseResult r = ndi::ParseTx(Bytes(reply), reply.size(), tx);
  ASSERT_TRUE(r.Ok()) << ndi::ParseCodeName(r.Code) << " at " << r.Offset;
  ASSERT_EQ(tx.Count, 1);
  const auto& h = tx.Handles[0];
  EXPECT_EQ(h.Handle, 1);
  EXPECT_EQ(h.State, ndi::HandleState::Valid);
  EXPECT_DOUBLE_EQ(h.Quaternion[0], 1.0);
  EXPECT_DOUBLE_EQ(h.Translation[0], 10.0);
  EXPECT_DOUBLE_EQ(h.Translation[1], -20.5);
  EXPECT_DOUBLE_EQ(h.Translation[2], -1500.25);
  EXPECT_NEAR(h.Error, 0.1234, 1e-12);
  EXPECT_EQ(h.PortStatus, 0x31u);
  EXPECT_EQ(h.Frame, 0x1Au);
  EXPECT_FALSE(h.OutOfVolume());
  EXPECT_EQ(tx.SystemStatus, 0);
}

TEST(NdiTx, MissingDisabledUnoccupied) {
  const std::string payload =
      "040A+05000+05000-05000+05000+001025-002050-150075+0125000000071000004D2\n"
      "0BMISSING00000031000004D2\n0CDISABLED\n0DUNOCCUPIED\n0004";
  const std::string reply = WithCrc(payload);
  ndi::TrackingReply tx;
  ASSERT_TRUE(ndi::ParseTx(Bytes(reply), reply.size(), tx).Ok());
  ASSERT_EQ(tx.Count, 4);
  EXPECT_EQ(tx.Handles[0].State, ndi::HandleState::Valid);
  EXPECT_TRUE(tx.Handles[0].OutOfVolume());
  EXPECT_DOUBLE_EQ(tx.Handles[0].Quaternion[2], -0.5);
  EXPECT_EQ(tx.Handles[0].Frame, 1234u);
  EXPECT_EQ(tx.Handles[1].State, ndi::HandleState::Missing);
  EXPECT_EQ(tx.Handles[1].Frame, 1234u);
  EXPECT_EQ(tx.Handles[2].State, ndi::HandleState::Disabled);
  EXPECT_EQ(tx.Handles[2].Handle, 0x0C);
  EXPECT_EQ(tx.Handles[3].State, ndi::HandleState::Unoccupied);
  EXPECT_EQ(tx.SystemStatus, 0x0004);
}

TEST(NdiTx, MalformedAndTruncatedGiveClearErrors) {
  const std::string good = "0101+10000+00000+00000+00000+001000-002050-150025+01234000000310000001A\n0000";
  ndi::TrackingReply tx;
  // Cut the payload short (CRC recomputed so only the content is wrong).
  std::string cut = WithCrc(good.substr(0, 30));
  ndi::ParseResult r = ndi::ParseTx(Bytes(cut), cut.size(), tx);
  EXPECT_EQ(r.Code, ndi::ParseCode::Truncated);
  EXPECT_EQ(r.Offset, 4u);
  std::string letters = good;
  letters[10] = 'x';
  letters = WithCrc(letters);
  r = ndi::ParseTx(Bytes(letters), letters.size(), tx);
  EXPECT_EQ(r.Code, ndi::ParseCode::BadFormat);
  EXPECT_EQ(r.Offset, 10u);  // the second quaternion field, where the x is
  std::string many = WithCrc("FF");
  EXPECT_EQ(ndi::ParseTx(Bytes(many), many.size(), tx).Code, ndi::ParseCode::TooManyHandles);
  std::string trailing = WithCrc(good + "00");
  EXPECT_EQ(ndi::ParseTx(Bytes(trailing), trailing.size(), tx).Code, ndi::ParseCode::BadFormat);
  std::string error = WithCrc("ERROR0C");
  r = ndi::ParseTx(Bytes(error), error.size(), tx);
  EXPECT_EQ(r.Code, ndi::ParseCode::DeviceError);
  EXPECT_EQ(r.DeviceError, 0x0C);
}

TEST(NdiBx, ValidMissingDisabledOutOfVolume) {
  const std::vector<uint8_t> frame = BxFrame(SampleBxBody());
  size_t length = 0;
  ASSERT_TRUE(ndi::FindFrame(frame.data(), frame.size(), length).Ok());
  EXPECT_EQ(length, frame.size());
  ndi::TrackingReply bx;
  const ndi::ParseResult r = ndi::ParseBx(frame.data(), frame.size(), bx);
  ASSERT_TRUE(r.Ok()) << ndi::ParseCodeName(r.Code) << " at " << r.Offset;
  ASSERT_EQ(bx.Count, 4);
  EXPECT_EQ(bx.Handles[0].Handle, 0x0A);
  EXPECT_EQ(bx.Handles[0].State, ndi::HandleState::Valid);
  EXPECT_DOUBLE_EQ(bx.Handles[0].Quaternion[2], -0.5);
  EXPECT_DOUBLE_EQ(bx.Handles[0].Translation[2], -1500.75);
  EXPECT_DOUBLE_EQ(bx.Handles[0].Error, 0.125);
  EXPECT_EQ(bx.Handles[0].Frame, 1234u);
  EXPECT_FALSE(bx.Handles[0].OutOfVolume());
  EXPECT_TRUE(bx.Handles[1].OutOfVolume());
  EXPECT_EQ(bx.Handles[2].State, ndi::HandleState::Missing);
  EXPECT_EQ(bx.Handles[2].PortStatus, 0x31u);
  EXPECT_EQ(bx.Handles[3].State, ndi::HandleState::Disabled);
}

TEST(NdiBx, CorruptTruncatedAndErrorReplies) {
  std::vector<uint8_t> frame = BxFrame(SampleBxBody());
  ndi::TrackingReply bx;
  std::vector<uint8_t> badBody = frame;
  badBody[10] ^= 0x01;
  EXPECT_EQ(ndi::ParseBx(badBody.data(), badBody.size(), bx).Code, ndi::ParseCode::BadCrc);
  std::vector<uint8_t> badHeader = frame;
  badHeader[2] ^= 0x01;
  EXPECT_EQ(ndi::ParseBx(badHeader.data(), badHeader.size(), bx).Code, ndi::ParseCode::BadCrc);
  EXPECT_EQ(ndi::ParseBx(frame.data(), frame.size() - 3, bx).Code, ndi::ParseCode::Truncated);
  size_t length = 0;
  EXPECT_EQ(ndi::FindFrame(frame.data(), frame.size() - 3, length).Code, ndi::ParseCode::Incomplete);
  // A body whose handle count promises more than it holds (CRCs valid).
  std::vector<uint8_t> body = SampleBxBody();
  body.resize(20);
  std::vector<uint8_t> shortFrame = BxFrame(body);
  const ndi::ParseResult r = ndi::ParseBx(shortFrame.data(), shortFrame.size(), bx);
  EXPECT_EQ(r.Code, ndi::ParseCode::Truncated);
  EXPECT_EQ(r.Offset, 6u + 3u);
  std::vector<uint8_t> badStatus = SampleBxBody();
  badStatus[2] = 0x08;
  std::vector<uint8_t> badStatusFrame = BxFrame(badStatus);
  EXPECT_EQ(ndi::ParseBx(badStatusFrame.data(), badStatusFrame.size(), bx).Code, ndi::ParseCode::BadFormat);
  const std::string error = WithCrc("ERROR0C");
  const ndi::ParseResult e = ndi::ParseBx(Bytes(error), error.size(), bx);
  EXPECT_EQ(e.Code, ndi::ParseCode::DeviceError);
  EXPECT_EQ(e.DeviceError, 0x0C);
}

TEST(NdiPhsr, HandleLists) {
  uint8_t handles[8];
  int count = 0;
  const std::string payload = "020A0310B001";
  ASSERT_TRUE(ndi::ParsePhsr(payload.data(), payload.size(), handles, 8, count).Ok());
  ASSERT_EQ(count, 2);
  EXPECT_EQ(handles[0], 0x0A);
  EXPECT_EQ(handles[1], 0x0B);
  EXPECT_EQ(ndi::ParsePhsr("03", 2, handles, 8, count).Code, ndi::ParseCode::Truncated);
}

// PHINF reply option 0021: 33 characters of basic information, then the port location as the
// NDI API lays it out (ndicapi's ndiGetPHINFPortLocation: 8 device number, 1 system, 1 wired/
// wireless, 2 port "01"-"12", 2 channel), numbered as PLUS's PortName (channel * 100 + port - 1).
TEST(NdiPhinf, PortLocationGivesPlusWiredPortNumber) {
  const std::string basic = std::string("01000000") + "NDI         " + "001" + "34801401" + "31";
  ASSERT_EQ(basic.size(), 33u);
  ndi::PortLocation location;
  std::string reply = basic + "3A1B2C3D" + "1" + "0" + "03" + "01";  // Aurora, wired port 3, channel 1
  ASSERT_TRUE(ndi::ParsePhinfPortLocation(reply.data(), reply.size(), location).Ok());
  EXPECT_TRUE(location.Wired);
  EXPECT_EQ(location.WiredPort, 102);
  reply = basic + "00000000" + "0" + "0" + "01" + "00";  // Polaris, wired port 1: PortName 0
  ASSERT_TRUE(ndi::ParsePhinfPortLocation(reply.data(), reply.size(), location).Ok());
  EXPECT_EQ(location.WiredPort, 0);
  reply = basic + "00000000" + "0" + "1" + "0A" + "00";  // a wireless (passive) tool
  ASSERT_TRUE(ndi::ParsePhinfPortLocation(reply.data(), reply.size(), location).Ok());
  EXPECT_FALSE(location.Wired);
  EXPECT_EQ(location.WiredPort, -1);
  EXPECT_EQ(ndi::ParsePhinfPortLocation(reply.data(), 40, location).Code, ndi::ParseCode::Truncated);
  EXPECT_EQ(ndi::ParsePhinfPortLocation("UNOCCUPIED", 10, location).Code, ndi::ParseCode::Truncated);
  reply = basic + "00000000" + "0" + "X" + "01" + "00";
  EXPECT_EQ(ndi::ParsePhinfPortLocation(reply.data(), reply.size(), location).Code, ndi::ParseCode::BadFormat);
  reply = basic + "00000000" + "0" + "0" + "00" + "00";  // no port 0
  EXPECT_EQ(ndi::ParsePhinfPortLocation(reply.data(), reply.size(), location).Code, ndi::ParseCode::BadFormat);
}

TEST(NdiRom, BuildAndValidate) {
  auto bytes = rom::Build("RP-TEST", {{0, 0, 0}, {0, 50, 0}, {40, 0, 0}});
  std::string error;
  ASSERT_EQ(bytes.size(), rom::Size);
  EXPECT_TRUE(rom::Validate(bytes, error)) << error;
  EXPECT_EQ(rom::PartNumber(bytes), "RP-TEST");
  EXPECT_EQ(rom::MarkerCount(bytes), 3);
  bytes[100] ^= 0xFF;
  EXPECT_FALSE(rom::Validate(bytes, error));
  EXPECT_EQ(error.rfind("tool definition checksum mismatch", 0), 0u) << error;
}

// Randomised robustness: mutate and cut valid replies; the parsers must never read out of
// bounds (run under ASan/TSan builds too) and must report a code other than Ok for anything
// whose CRC no longer matches.
TEST(NdiFuzz, RandomMutationsNeverCrash) {
  std::mt19937 rng(1234);
  const std::string tx = WithCrc(
      "030A+05000+05000-05000+05000+001025-002050-150075+0125000000071000004D2\n0BMISSING00000031000004D2\n0CDISABLED\n0000");
  const std::vector<uint8_t> bx = BxFrame(SampleBxBody());
  int rejected = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    std::vector<uint8_t> data = (iteration % 2) ? bx : std::vector<uint8_t>(tx.begin(), tx.end());
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      switch (rng() % 3) {
        case 0: data[rng() % data.size()] = static_cast<uint8_t>(rng()); break;
        case 1: data.resize(rng() % (data.size() + 1)); break;
        default: data.insert(data.begin() + static_cast<long>(rng() % (data.size() + 1)), static_cast<uint8_t>(rng())); break;
      }
      if (data.empty()) data.push_back(0);
    }
    // Parse from a heap copy of exactly the right size so ASan catches any over-read.
    std::unique_ptr<uint8_t[]> exact(new uint8_t[data.size()]);
    std::memcpy(exact.get(), data.data(), data.size());
    ndi::TrackingReply reply;
    size_t length;
    ndi::FindFrame(exact.get(), data.size(), length);
    const ndi::ParseResult r = (iteration % 2) ? ndi::ParseBx(exact.get(), data.size(), reply)
                                               : ndi::ParseTx(exact.get(), data.size(), reply);
    if (!r.Ok()) ++rejected;
    EXPECT_LE(reply.Count, ndi::MaxHandles);
  }
  // CRC-16 lets through about 1 in 65536 random corruptions; nearly all must be rejected.
  EXPECT_GT(rejected, 19900);
}
