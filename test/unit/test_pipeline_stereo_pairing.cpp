// StereoPairing (pipeline/stereo_pairing.h): which right frame goes with which left frame, on stamp streams.
#include <gtest/gtest.h>
#include <iraf_vo/pipeline/stereo_pairing.h>

using namespace iraf_vo;

namespace {

using Kind = StereoPairing::Kind;
constexpr int64_t kMs = 1000000;
int64_t stampOf(int i) { return 1000 * 1000 * kMs + i * 50 * kMs; }  // 20 Hz from t = 1000 s

struct Log {
  std::vector<StereoPairing::Decision> d;
  void add(const std::vector<StereoPairing::Decision>& v) { d.insert(d.end(), v.begin(), v.end()); }
  long count(Kind k) const {
    long n = 0;
    for (const auto& x : d) n += x.kind == k;
    return n;
  }
};

long countLevel(const std::vector<SessionMessage>& m, SessionMessage::Level l) {
  long n = 0;
  for (const auto& x : m) n += x.level == l;
  return n;
}

TEST(StereoPairing, EqualStampsPairInEitherArrivalOrder) {
  StereoPairing p;
  Log log;
  for (int i = 0; i < 10; ++i) {
    const double now = 0.05 * i;
    if (i % 2) {
      log.add(p.addLeft(stampOf(i), now));
      EXPECT_TRUE(log.d.empty() || log.d.back().left_ns != stampOf(i)) << "a left frame waits for its partner";
      log.add(p.addRight(stampOf(i), now + 0.01));
    } else {
      log.add(p.addRight(stampOf(i), now));
      log.add(p.addLeft(stampOf(i), now + 0.01));
    }
  }
  ASSERT_EQ(log.d.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(log.d[i].kind, Kind::kPair) << i;
    EXPECT_EQ(log.d[i].left_ns, stampOf(i));
    EXPECT_EQ(log.d[i].right_ns, stampOf(i));
  }
  EXPECT_TRUE(p.takeMessages().empty()) << "a healthy stereo stream says nothing";
  EXPECT_EQ(p.counters().pairs, 10);
  EXPECT_EQ(p.counters().left_only, 0);
  EXPECT_EQ(p.counters().dropped_right, 0);
}

TEST(StereoPairing, JitterWithinTolerancePairsBeyondItDropsTheRightFrame) {
  StereoPairingParams params;
  params.tolerance = 0.003;
  StereoPairing p(params);
  Log log;
  const int64_t offset[] = {2 * kMs, -3 * kMs, 4 * kMs, -9 * kMs, 1 * kMs, 20 * kMs};
  for (int i = 0; i < 6; ++i) {
    log.add(p.addLeft(stampOf(i), 0.05 * i));
    log.add(p.addRight(stampOf(i) + offset[i], 0.05 * i + 0.001));
  }
  log.add(p.flush());
  // 0, 1, 4 pair; 2 (+4 ms) and 3 (-9 ms) and 5 (+20 ms) are left-only, their right frames dropped.
  EXPECT_EQ(p.counters().pairs, 3);
  EXPECT_EQ(p.counters().left_only, 3);
  EXPECT_EQ(p.counters().dropped_right, 3);
  EXPECT_EQ(log.count(Kind::kPair) + log.count(Kind::kLeftOnly), 6) << "every left frame is delivered once";
  for (const auto& d : log.d)
    if (d.kind == Kind::kPair) {
      EXPECT_LE(std::llabs(d.right_ns - d.left_ns), 3 * kMs);
    }
}

TEST(StereoPairing, TheClosestRightFrameWins) {
  StereoPairingParams params;
  params.tolerance = 0.02;
  StereoPairing p(params);
  Log log;
  log.add(p.addRight(stampOf(0) - 15 * kMs, 0.0));
  log.add(p.addRight(stampOf(0) + 2 * kMs, 0.0));
  log.add(p.addLeft(stampOf(0), 0.01));
  ASSERT_EQ(log.d.size(), 2u);
  EXPECT_EQ(log.d[0].kind, Kind::kDropRight);
  EXPECT_EQ(log.d[1].kind, Kind::kPair);
  EXPECT_EQ(log.d[1].right_ns, stampOf(0) + 2 * kMs);
}

// The right camera stops for frames 10-29 and comes back: the left frames go on (waiting once), one warning when it
// stops, one notice when it is back. Left frame 30 does not wait (the right camera is still missing when it
// arrives): its right partner, 5 ms later, is dropped and the pairs resume at frame 31.
TEST(StereoPairing, ARightCameraThatStopsAndComesBack) {
  StereoPairingParams params;
  params.max_wait = 0.12;
  StereoPairing p(params);
  Log log;
  std::vector<SessionMessage> messages;
  long waited = 0;  // left frames not decided when they arrived
  for (int i = 0; i < 40; ++i) {
    const double now = 0.05 * i;
    log.add(p.poll(now));
    const size_t before = log.d.size();
    log.add(p.addLeft(stampOf(i), now));
    const bool right = i < 10 || i >= 30;
    if (right) log.add(p.addRight(stampOf(i), now + 0.005));
    if (!right && log.d.size() == before) ++waited;
    for (auto& m : p.takeMessages()) messages.push_back(m);
  }
  log.add(p.poll(10.0));
  EXPECT_EQ(p.counters().pairs, 19);
  EXPECT_EQ(p.counters().left_only, 21);
  EXPECT_EQ(p.counters().dropped_right, 1);
  EXPECT_EQ(p.counters().missing_events, 1);
  // The first left frame without a partner waits max_wait (0.12 s), and so do the two that arrive meanwhile; the
  // later ones go at once.
  EXPECT_EQ(waited, 3);
  EXPECT_EQ(countLevel(messages, SessionMessage::Level::kWarn), 1);
  EXPECT_EQ(countLevel(messages, SessionMessage::Level::kInfo), 1);
  ASSERT_EQ(messages.size(), 2u);
  EXPECT_NE(messages[0].text.find("left camera only"), std::string::npos) << messages[0].text;
  EXPECT_NE(messages[1].text.find("after 21 left-only"), std::string::npos) << messages[1].text;
  // In order: every left frame once.
  int64_t last = 0;
  for (const auto& d : log.d) {
    if (d.kind == Kind::kDropRight) continue;
    EXPECT_GT(d.left_ns, last);
    last = d.left_ns;
  }
  EXPECT_FALSE(p.rightMissing());
}

// A right stream that resumes late (each right frame after its left one already went left-only) pairs again from the
// next frame: a right arrival makes the left frames wait again.
TEST(StereoPairing, RecoversWhenTheRightStreamLagsAfterAGap) {
  StereoPairingParams params;
  params.max_wait = 0.1;
  StereoPairing p(params);
  Log log;
  for (int i = 0; i < 5; ++i) log.add(p.addLeft(stampOf(i), 0.05 * i)), log.add(p.poll(0.05 * i + 0.2));
  EXPECT_TRUE(p.rightMissing());
  // The right camera comes back 80 ms behind the left one.
  for (int i = 5; i < 12; ++i) {
    log.add(p.addLeft(stampOf(i), 0.05 * i));
    log.add(p.addRight(stampOf(i), 0.05 * i + 0.08));
  }
  EXPECT_FALSE(p.rightMissing());
  EXPECT_GE(p.counters().pairs, 6) << "at most the first frame after the gap is lost to the lag";
}

TEST(StereoPairing, FlushAndBoundedRightQueue) {
  StereoPairingParams params;
  params.max_pending_right = 3;
  StereoPairing p(params);
  Log log;
  for (int i = 0; i < 8; ++i) log.add(p.addRight(stampOf(i), 0.0));  // no left frame (left chain not started)
  EXPECT_EQ(p.pendingRight(), 3u);
  EXPECT_EQ(log.count(Kind::kDropRight), 5);
  log.add(p.addLeft(stampOf(20), 0.0));
  log.add(p.flush());
  EXPECT_EQ(p.pendingLeft(), 0u);
  EXPECT_EQ(p.pendingRight(), 0u);
  EXPECT_EQ(log.count(Kind::kDropRight), 8);
  EXPECT_EQ(log.count(Kind::kLeftOnly), 1);
}

}  // namespace
