/* Requests to a daemon: one STATS, a TOUR with its progress, and fresh clients one after another,
 * each sending one STATS with no resend (the first reply of a new client must arrive). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>

#include "vendor_client.h"

enum { kMatchMs = 20000, kCallMs = 30000, kResendMs = 1000, kFreshReplyMs = 2000 };

static void open_matched(vc_client *client, int domain, bool with_progress) {
  vc_client_open(client, domain, with_progress);
  if (!vc_wait_matched(client->query_writer, vc_now_ms() + kMatchMs)) {
    vc_fail("the query writer matched no reader within %d ms: is a daemon running on domain %d?", kMatchMs, domain);
  }
}

int vc_cmd_stats(int domain, const char *server, const char *scene) {
  vc_client client;
  open_matched(&client, domain, false);
  ispars_msg_QueryRequest request;
  vc_query_init(&client, &request, ispars_msg_STATS, server, scene);
  static ispars_msg_Reply reply;
  vc_wait wait = {.deadline_ms = vc_now_ms() + kCallMs, .resend_ms = kResendMs};
  const double t0 = vc_now_ms();
  if (!vc_call(&client, &request, &wait, &reply)) vc_fail("no reply to STATS within %d ms", kCallMs);
  const double latency = vc_now_ms() - t0;
  if (!reply.ok) vc_fail("STATS refused: %s", reply.error);
  printf("{\"client\":\"%s\",\"request_seq\":%llu,\"sends\":%d,\"latency_ms\":%.3f,\"server_id\":", client.prefix,
         (unsigned long long)reply.request_seq, wait.sends, latency);
  vc_json_string(reply.server_id);
  putchar(',');
  vc_json_status(&reply.status);
  puts("}");
  vc_reply_free(&reply);
  vc_client_close(&client);
  return 0;
}

typedef struct tour_progress {
  int count;
  double first_seconds;
  double best_cost;
} tour_progress;

static void on_progress(const ispars_msg_TourProgress *progress, void *context) {
  tour_progress *seen = context;
  if (seen->count++ == 0) seen->first_seconds = progress->seconds;
  seen->best_cost = progress->cost;
}

int vc_cmd_tour(int domain, const char *server, const char *scene, double budget) {
  vc_client client;
  open_matched(&client, domain, true);  /* the progress reader is made before the request */
  ispars_msg_QueryRequest request;
  vc_query_init(&client, &request, ispars_msg_TOUR, server, scene);
  request.args._u.tour.budget = budget;
  request.args._u.tour.seed = 1;
  static ispars_msg_Reply reply;
  tour_progress seen = {0, 0.0, 0.0};
  vc_wait wait = {.deadline_ms = vc_now_ms() + budget * 1000.0 + kCallMs, .resend_ms = kResendMs,
                  .on_progress = on_progress, .context = &seen};
  if (!vc_call(&client, &request, &wait, &reply)) vc_fail("no reply to TOUR within %.0f s", budget + kCallMs / 1000.0);
  if (!reply.ok) vc_fail("TOUR refused: %s", reply.error);
  if (reply.body._d != ispars_msg_TOUR) vc_fail("a TOUR reply with a body of operation %d", (int)reply.body._d);
  const ispars_msg_TourResult *tour = &reply.body._u.tour;
  printf("{\"client\":\"%s\",\"sends\":%d,\"progress\":%d,\"first_progress_s\":%.3f,\"last_progress_cost\":%.6f,"
         "\"cost\":%.6f,\"covered\":%u,\"target_count\":%u,\"lower_bound\":%.6f,\"valid\":%s,\"walk\":%u,"
         "\"version\":%llu}\n",
         client.prefix, wait.sends, seen.count, seen.first_seconds, seen.best_cost, tour->cost, tour->covered,
         tour->target_count, tour->lower_bound, tour->valid ? "true" : "false", tour->walk._length,
         (unsigned long long)tour->version);
  vc_reply_free(&reply);
  vc_client_close(&client);
  return 0;
}

static int by_value(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* One fresh client's first STATS: its latency in ms, or a negative value when no reply came. */
static double fresh_client(int domain, const char *server, const char *scene) {
  vc_client client;
  open_matched(&client, domain, false);
  ispars_msg_QueryRequest request;
  vc_query_init(&client, &request, ispars_msg_STATS, server, scene);
  static ispars_msg_Reply reply;
  const double t0 = vc_now_ms();
  vc_wait wait = {.deadline_ms = t0 + kFreshReplyMs, .resend_ms = 0};
  double latency = -1.0;
  if (vc_call(&client, &request, &wait, &reply)) {
    latency = vc_now_ms() - t0;
    vc_reply_free(&reply);
  }
  vc_client_close(&client);
  return latency;
}

int vc_cmd_fresh(int domain, int count, const char *server, const char *scene) {
  double *latencies = calloc((size_t)count, sizeof *latencies);
  if (latencies == NULL) vc_fail("out of memory");
  int answered = 0, lost = 0;
  for (int i = 0; i < count; ++i) {
    const double latency = fresh_client(domain, server, scene);
    if (latency < 0) {
      ++lost;
      fprintf(stderr, "ispars-cyclone: fresh client %d of %d: no reply within %d ms\n", i + 1, count, kFreshReplyMs);
    } else {
      latencies[answered++] = latency;
    }
  }
  qsort(latencies, (size_t)answered, sizeof *latencies, by_value);
  printf("{\"clients\":%d,\"answered\":%d,\"lost\":%d", count, answered, lost);
  if (answered > 0) {
    const int p95 = (answered * 95 + 99) / 100 - 1;
    printf(",\"latency_ms\":{\"min\":%.3f,\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f}", latencies[0],
           latencies[answered / 2], latencies[p95], latencies[answered - 1]);
  }
  puts("}");
  free(latencies);
  return 0;
}
