/* A request and its reply, as any client of isparsd makes them: replies and tour progress read in
 * the client's own partition, request_seq never 0, and every Reply not awaited ignored. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include "vendor_client.h"

void vc_client_open(vc_client *client, int domain, bool with_progress) {
  memset(client, 0, sizeof *client);
  client->participant = vc_participant(domain, client->prefix);
  client->next_seq = 1;
  char partition[64];
  snprintf(partition, sizeof partition, "ispars.client.%s", client->prefix);
  dds_qos_t *subscriber_qos = dds_create_qos();
  dds_qset_partition1(subscriber_qos, partition);
  const dds_entity_t subscriber = dds_create_subscriber(client->participant, subscriber_qos, NULL);
  dds_delete_qos(subscriber_qos);
  vc_check(subscriber, "create subscriber");
  dds_qos_t *qos = vc_request_reply_qos();
  /* The readers first, so each is there before the daemon hears of the request. */
  if (with_progress) {
    client->progress_reader = vc_reader(subscriber, &ispars_msg_TourProgress_desc, "ispars/tour_progress", qos);
  }
  client->reply_reader = vc_reader(subscriber, &ispars_msg_Reply_desc, "ispars/reply", qos);
  client->query_writer = vc_writer(client->participant, &ispars_msg_QueryRequest_desc, "ispars/query", qos);
  dds_delete_qos(qos);
}

void vc_client_close(vc_client *client) {
  if (client->participant > 0) vc_check(dds_delete(client->participant), "delete participant");
  client->participant = 0;
}

void vc_query_init(vc_client *client, ispars_msg_QueryRequest *request, ispars_msg_Operation operation,
                   const char *server, const char *scene) {
  memset(request, 0, sizeof *request);
  snprintf(request->client_id, sizeof request->client_id, "%s", client->prefix);
  request->request_seq = client->next_seq++;
  snprintf(request->server_id, sizeof request->server_id, "%s", server);
  request->protocol = ispars_msg_PROTOCOL_VERSION;
  snprintf(request->scene, sizeof request->scene, "%s", scene);
  request->args._d = operation;
}

void vc_reply_free(ispars_msg_Reply *reply) { dds_sample_free(reply, &ispars_msg_Reply_desc, DDS_FREE_CONTENTS); }

/* Passes each TourProgress of request `seq` to `on_progress`. */
static void take_progress(vc_client *client, uint64_t seq, vc_progress_fn on_progress, void *context) {
  for (;;) {
    ispars_msg_TourProgress progress;
    memset(&progress, 0, sizeof progress);
    void *sample = &progress;
    dds_sample_info_t info;
    const dds_return_t n = dds_take(client->progress_reader, &sample, &info, 1, 1);
    vc_check(n, "take ispars/tour_progress");
    if (n == 0) return;
    if (info.valid_data && progress.request_seq == seq && on_progress != NULL) on_progress(&progress, context);
  }
}

/* Takes replies until the one of request `seq`: true with it in `out`. */
static bool take_reply(vc_client *client, uint64_t seq, ispars_msg_Reply *out) {
  for (;;) {
    memset(out, 0, sizeof *out);
    void *sample = out;
    dds_sample_info_t info;
    const dds_return_t n = dds_take(client->reply_reader, &sample, &info, 1, 1);
    vc_check(n, "take ispars/reply");
    if (n == 0) return false;
    if (info.valid_data && out->request_seq == seq) return true;
    vc_reply_free(out);  /* not awaited: a route-open Reply (request_seq 0) or an old one */
  }
}

bool vc_call(vc_client *client, const ispars_msg_QueryRequest *request, vc_wait *wait, ispars_msg_Reply *out) {
  const dds_entity_t waitset = dds_create_waitset(client->participant);
  vc_check(waitset, "create waitset");
  const dds_entity_t replies = dds_create_readcondition(client->reply_reader, DDS_ANY_STATE);
  vc_check(dds_waitset_attach(waitset, replies, 0), "attach reply condition");
  dds_entity_t progress = 0;
  if (client->progress_reader > 0) {
    progress = dds_create_readcondition(client->progress_reader, DDS_ANY_STATE);
    vc_check(dds_waitset_attach(waitset, progress, 1), "attach progress condition");
  }
  const uint64_t seq = request->request_seq;
  bool answered = false;
  double next_send = vc_now_ms();
  wait->sends = 0;
  for (;;) {
    if (progress > 0) take_progress(client, seq, wait->on_progress, wait->context);
    if ((answered = take_reply(client, seq, out))) break;
    const double now = vc_now_ms();
    if (now >= wait->deadline_ms) break;
    if (now >= next_send && (wait->sends == 0 || wait->resend_ms > 0)) {
      vc_check(dds_write(client->query_writer, request), "write ispars/query");
      ++wait->sends;
      next_send = wait->resend_ms > 0 ? now + wait->resend_ms : wait->deadline_ms;
    }
    const double until = next_send < wait->deadline_ms ? next_send : wait->deadline_ms;
    const double left = until - vc_now_ms();
    if (left > 0) vc_check(dds_waitset_wait(waitset, NULL, 0, DDS_USECS((int64_t)(left * 1000.0) + 1)), "wait for a reply");
  }
  /* Progress written just before the reply may have arrived with it. */
  if (answered && progress > 0) take_progress(client, seq, wait->on_progress, wait->context);
  dds_delete(waitset);
  dds_delete(replies);
  if (progress > 0) dds_delete(progress);
  return answered;
}
