#include <gtest/gtest.h>

#include "executors/executor.hpp"
#include "executors/publisher.hpp"
#include "executors/subscription.hpp"
#include "executors/topic.hpp"
#include "tests/executors/test_messages.hpp"

namespace scancrew {
namespace {

using test::Blob;
using test::Counter;

struct Fixture {
  WallClock clock;
  CallbackGroup group{"g", CallbackGroup::Type::kMutuallyExclusive};
};

class ZeroCopy : public ::testing::TestWithParam<size_t> {};

TEST_P(ZeroCopy, EverySubscriberReceivesThePublishersBuffer) {
  Fixture f;
  auto topic = std::make_shared<Topic<Blob>>("/blob", 4);
  Publisher<Blob> pub(topic, 7, &f.clock, nullptr);
  std::vector<const uint8_t*> seen;
  auto record = [&](Sample<Blob>&& s) { seen.push_back(s->bytes.data()); };
  Subscription<Blob> a(topic, {.depth = 2}, record, f.group, nullptr);
  Subscription<Blob> b(topic, {.depth = 2}, record, f.group, nullptr);
  Subscription<Blob> c(topic, {.depth = 2}, record, f.group, nullptr);

  auto loan = pub.loan();
  ASSERT_TRUE(loan);
  (*loan)->bytes.assign(GetParam(), 0xAB);
  const uint8_t* written = (*loan)->bytes.data();
  auto delivered = pub.publish(std::move(*loan));
  ASSERT_TRUE(delivered);
  EXPECT_EQ(*delivered, 3u);
  for (Subscription<Blob>* s : {&a, &b, &c}) EXPECT_TRUE(s->execute());
  ASSERT_EQ(seen.size(), 3u);
  for (const uint8_t* p : seen) EXPECT_EQ(p, written);
}

INSTANTIATE_TEST_SUITE_P(PayloadSizes, ZeroCopy,
                         ::testing::Values(size_t{64}, size_t{4096}, size_t{1} << 20,
                                           size_t{16} << 20));

TEST(Topic, SlotGoesBackToThePoolWhenTheLastReaderDropsIt) {
  Fixture f;
  auto topic = std::make_shared<Topic<Counter>>("/c", 2);
  Publisher<Counter> pub(topic, 0, &f.clock, nullptr);
  Sample<Counter> kept_a, kept_b;
  Subscription<Counter> a(
      topic, {.depth = 1}, [&](Sample<Counter>&& s) { kept_a = std::move(s); }, f.group, nullptr);
  Subscription<Counter> b(
      topic, {.depth = 1}, [&](Sample<Counter>&& s) { kept_b = s; }, f.group, nullptr);
  ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
  EXPECT_EQ(topic->pool().available(), 1u);  // queued in both
  ASSERT_TRUE(a.execute());
  ASSERT_TRUE(b.execute());
  EXPECT_EQ(topic->pool().available(), 1u);  // held by both callbacks' copies
  kept_a.reset();
  EXPECT_EQ(topic->pool().available(), 1u);
  kept_b.reset();
  EXPECT_EQ(topic->pool().available(), 2u);
}

TEST(Topic, LoanFromAnExhaustedPoolIsANamedError) {
  Fixture f;
  auto topic = std::make_shared<Topic<Counter>>("/c", 2);
  Publisher<Counter> pub(topic, 0, &f.clock, nullptr);
  auto l1 = pub.loan(), l2 = pub.loan();
  ASSERT_TRUE(l1 && l2);
  auto l3 = pub.loan();
  ASSERT_FALSE(l3);
  EXPECT_EQ(l3.error(), LoanError::kPoolExhausted);
  EXPECT_FALSE(to_string(l3.error()).empty());
  EXPECT_EQ(topic->stats().loan_failures, 1u);
  { auto dropped = std::move(l1).value(); }  // an unpublished loan returns its slot
  EXPECT_TRUE(pub.loan());
}

TEST(Topic, KeepLastDropsTheOldestAndCountsIt) {
  Fixture f;
  auto topic = std::make_shared<Topic<Counter>>("/c", 8);
  Publisher<Counter> pub(topic, 0, &f.clock, nullptr);
  std::vector<uint64_t> got;
  Subscription<Counter> sub(
      topic, {.depth = 2, .history = History::kKeepLast},
      [&](Sample<Counter>&& s) { got.push_back(s->value); }, f.group, nullptr);
  for (uint64_t v = 1; v <= 5; ++v) {
    auto loan = pub.loan();
    ASSERT_TRUE(loan) << "pool must not leak slots of dropped samples";
    (*loan)->value = v;
    ASSERT_TRUE(pub.publish(std::move(*loan)));
  }
  while (sub.execute()) {
  }
  EXPECT_EQ(got, (std::vector<uint64_t>{4, 5}));
  EXPECT_EQ(sub.queue().dropped.load(), 3u);
  EXPECT_EQ(topic->stats().dropped, 3u);
  EXPECT_EQ(topic->pool().available(), 8u);
}

TEST(Topic, FailFastRejectsThePublishForEveryoneWhenAQueueIsFull) {
  Fixture f;
  auto topic = std::make_shared<Topic<Counter>>("/c", 8);
  Publisher<Counter> pub(topic, 0, &f.clock, nullptr);
  int calls_a = 0, calls_b = 0;
  Subscription<Counter> a(
      topic, {.depth = 1, .history = History::kFailFast}, [&](Sample<Counter>&&) { ++calls_a; },
      f.group, nullptr);
  Subscription<Counter> b(
      topic, {.depth = 4}, [&](Sample<Counter>&&) { ++calls_b; }, f.group, nullptr);
  ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
  auto second = pub.publish(std::move(*pub.loan()));
  ASSERT_FALSE(second);
  EXPECT_EQ(second.error(), PublishError::kQueueFull);
  while (a.execute()) {
  }
  while (b.execute()) {
  }
  EXPECT_EQ(calls_a, 1);
  EXPECT_EQ(calls_b, 1);  // the rejected sample reached nobody
  EXPECT_EQ(topic->stats().rejected, 1u);
  EXPECT_EQ(topic->pool().available(), 8u);
}

TEST(Topic, PublishStampsTheHeader) {
  SimClock clock;
  clock.advance_to(5'000);
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Counter>>("/c", 4);
  Publisher<Counter> pub(topic, 3, &clock, nullptr);
  std::vector<msg::Header> headers;
  Subscription<Counter> sub(
      topic, {.depth = 4}, [&](Sample<Counter>&& s) { headers.push_back(s->header); }, group,
      nullptr);
  ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
  auto loan = pub.loan();
  (*loan)->header.stamp_ns = 42;  // a capture time set by the writer is kept
  ASSERT_TRUE(pub.publish(std::move(*loan)));
  while (sub.execute()) {
  }
  ASSERT_EQ(headers.size(), 2u);
  EXPECT_EQ(headers[0].robot_id, 3u);
  EXPECT_EQ(headers[0].seq, 1u);
  EXPECT_EQ(headers[1].seq, 2u);
  EXPECT_EQ(headers[0].stamp_ns, 5'000);
  EXPECT_EQ(headers[1].stamp_ns, 42);
  EXPECT_GT(headers[1].publish_mono_ns, 0);
  EXPECT_GE(headers[1].publish_mono_ns, headers[0].publish_mono_ns);
}

TEST(Topic, ALoanFromAnotherTopicIsRejected) {
  Fixture f;
  auto t1 = std::make_shared<Topic<Counter>>("/a", 2);
  auto t2 = std::make_shared<Topic<Counter>>("/b", 2);
  Publisher<Counter> p1(t1, 0, &f.clock, nullptr);
  auto loan = t2->loan();
  auto r = p1.publish(std::move(*loan));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error(), PublishError::kInvalidLoan);
  EXPECT_EQ(t2->pool().available(), 2u);
}

TEST(Topic, StatsReportRateAndLatency) {
  Fixture f;
  auto topic = std::make_shared<Topic<Counter>>("/c", 4);
  Publisher<Counter> pub(topic, 0, &f.clock, nullptr);
  Subscription<Counter> sub(
      topic, {.depth = 4}, [](Sample<Counter>&&) {}, f.group, nullptr);
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
    ASSERT_TRUE(sub.execute());
  }
  const TopicStats s = topic->stats();
  EXPECT_EQ(s.published, 10u);
  EXPECT_EQ(s.taken, 10u);
  EXPECT_GT(s.rate_hz, 0.0);
  EXPECT_GT(s.latency_max_ns, 0u);
  EXPECT_LE(s.latency_p50_ns, s.latency_max_ns);
}

}  // namespace
}  // namespace scancrew
