// The metrics exposition: counters by operation and outcome, a cumulative latency histogram,
// samples built across rebuilds, gauges, and label values escaped.

#include <gtest/gtest.h>

#include "ispars/server/daemon_metrics.hpp"

namespace ispars::server {
namespace {

bool has_line(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

TEST(DaemonMetrics, RequestsAreCountedByOperationAndOutcomeWithACumulativeHistogram) {
  DaemonMetrics m;
  m.count_request("stats", RequestOutcome::ok, 0.0004);       // first bucket
  m.count_request("stats", RequestOutcome::ok, 0.003);        // le=0.005
  m.count_request("stats", RequestOutcome::refused, 0.0005);  // exactly on a bound: in that bucket
  m.count_request("stats", RequestOutcome::ok, 7.0);          // past the last bound: +Inf only
  m.count_request("build", RequestOutcome::busy, 0.0);
  const std::string text = m.render({});
  EXPECT_TRUE(has_line(text, "ispars_requests_total{operation=\"stats\",outcome=\"ok\"} 3")) << text;
  EXPECT_TRUE(has_line(text, "ispars_requests_total{operation=\"stats\",outcome=\"refused\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_requests_total{operation=\"build\",outcome=\"busy\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"0.0005\"} 2")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"0.0025\"} 2")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"0.005\"} 3")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"5\"} 3")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"+Inf\"} 4")) << text;
  EXPECT_TRUE(has_line(text, "ispars_request_duration_seconds_count{operation=\"stats\"} 4")) << text;
  EXPECT_NE(text.find("# TYPE ispars_request_duration_seconds histogram"), std::string::npos);
}

TEST(DaemonMetrics, SamplesBuiltCountIncreasesAndARebuildFromZeroCountsAfresh) {
  DaemonMetrics m;
  m.observe_samples("a", 1000);
  m.observe_samples("a", 1000);  // a status repeated
  m.observe_samples("a", 2500);
  m.observe_samples("b", 300);
  m.observe_samples("a", 0);  // dropped, or a replacing build started
  m.observe_samples("a", 400);
  EXPECT_TRUE(has_line(m.render({}), "ispars_samples_built_total 3200")) << m.render({});
}

TEST(DaemonMetrics, GaugesAreRenderedPerSceneWithEscapedLabels) {
  DaemonMetrics m;
  DaemonGauges g;
  g.scenes.push_back({"tower", "idle", 3000, 514, 2533, 200, 194});
  g.scenes.push_back({"odd\"na\\me", "building", 10, 2, 1, 200, 3});
  g.update_subscribers = 4;
  g.resident_bytes = 123456;
  g.memory_reserved_bytes = 2048;
  g.memory_leased_bytes = 512;
  g.handed_over = {{"tower", "d2"}};
  g.declined = 1;
  g.unservable = {"bridge"};
  const std::string text = m.render(g);
  EXPECT_TRUE(has_line(text, "ispars_fleet_handed_over{scene=\"tower\",to=\"d2\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_fleet_declined_scenes 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_stored_unservable{scene=\"bridge\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_scenes{state=\"idle\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_scenes{state=\"building\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_roadmap_vertices{scene=\"tower\"} 514")) << text;
  EXPECT_TRUE(has_line(text, "ispars_roadmap_edges{scene=\"odd\\\"na\\\\me\"} 1")) << text;
  EXPECT_TRUE(has_line(text, "ispars_update_subscribers 4")) << text;
  EXPECT_TRUE(has_line(text, "process_resident_memory_bytes 123456")) << text;
  EXPECT_TRUE(has_line(text, "ispars_memory_reserved_bytes 2048")) << text;
  EXPECT_TRUE(has_line(text, "ispars_memory_leased_bytes 512")) << text;
  EXPECT_GT(resident_memory_bytes(), 0u);
}

}  // namespace
}  // namespace ispars::server
