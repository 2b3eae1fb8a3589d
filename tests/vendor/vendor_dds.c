/* Cyclone DDS set up as isparsd's Fast DDS peers expect it: loopback only, the service's QoS, XCDR1,
 * and the rule for believing a status or an update (written by the daemon's own participant). */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vendor_client.h"

void vc_fail(const char *format, ...) {
  va_list args;
  va_start(args, format);
  fputs("ispars-cyclone: ", stderr);
  vfprintf(stderr, format, args);
  fputc('\n', stderr);
  va_end(args);
  exit(1);
}

double vc_now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1000.0 + (double)t.tv_nsec / 1e6;
}

void vc_check(dds_return_t rc, const char *what) {
  if (rc < 0) vc_fail("%s: %s", what, dds_strretcode(rc));
}

/* The Fast DDS side (idl/src/participant.cpp) sends discovery to 127.0.0.1 for participant ids
 * 0..31 and never uses multicast on lo: Cyclone takes a well-known port (an index of its own, not
 * an ephemeral port) and sends its discovery to the same 32 indices. ISPARS_CYCLONE_TRACE=FILE
 * writes Cyclone's trace there. */
void vc_configure(void) {
  static char config[1024];
  const char *trace = getenv("ISPARS_CYCLONE_TRACE");
  char tracing[384] = "";
  if (trace != NULL && trace[0] != '\0') {
    snprintf(tracing, sizeof tracing, "<Tracing><Verbosity>finest</Verbosity><OutputFile>%s</OutputFile></Tracing>",
             trace);
  }
  snprintf(config, sizeof config,
           "<CycloneDDS><Domain id=\"any\">"
           "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
           "<AllowMulticast>false</AllowMulticast></General>"
           "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
           "<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex>"
           "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>%s"
           "</Domain></CycloneDDS>",
           tracing);
  if (setenv("CYCLONEDDS_URI", config, 1) != 0) vc_fail("cannot set CYCLONEDDS_URI");
}

dds_entity_t vc_participant(int domain, char *prefix) {
  const dds_entity_t participant = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
  vc_check(participant, "create participant");
  dds_guid_t guid;
  vc_check(dds_get_guid(participant, &guid), "participant GUID");
  for (int i = 0; i < 12; ++i) snprintf(prefix + 2 * i, 3, "%02x", guid.v[i]);
  return participant;
}

static dds_qos_t *reliable(dds_durability_kind_t durability, int32_t depth) {
  dds_qos_t *qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_durability(qos, durability);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  const dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(qos, 1, xcdr1);
  return qos;
}

dds_qos_t *vc_request_reply_qos(void) { return reliable(DDS_DURABILITY_VOLATILE, 64); }
dds_qos_t *vc_state_qos(void) { return reliable(DDS_DURABILITY_TRANSIENT_LOCAL, 1); }
dds_qos_t *vc_updates_qos(void) { return reliable(DDS_DURABILITY_TRANSIENT_LOCAL, 256); }

static dds_entity_t topic(dds_entity_t parent, const dds_topic_descriptor_t *type, const char *name) {
  const dds_entity_t participant = dds_get_participant(parent);
  vc_check(participant, "participant of an entity");
  const dds_entity_t t = dds_create_topic(participant, type, name, NULL, NULL);
  if (t < 0) vc_fail("create topic %s: %s", name, dds_strretcode(t));
  return t;
}

dds_entity_t vc_reader(dds_entity_t parent, const dds_topic_descriptor_t *type, const char *topic_name,
                       const dds_qos_t *qos) {
  const dds_entity_t reader = dds_create_reader(parent, topic(parent, type, topic_name), qos, NULL);
  if (reader < 0) vc_fail("create reader of %s: %s", topic_name, dds_strretcode(reader));
  return reader;
}

dds_entity_t vc_writer(dds_entity_t parent, const dds_topic_descriptor_t *type, const char *topic_name,
                       const dds_qos_t *qos) {
  const dds_entity_t writer = dds_create_writer(parent, topic(parent, type, topic_name), qos, NULL);
  if (writer < 0) vc_fail("create writer of %s: %s", topic_name, dds_strretcode(writer));
  return writer;
}

bool vc_wait_matched(dds_entity_t writer, double deadline_ms) {
  for (;;) {
    dds_publication_matched_status_t status;
    vc_check(dds_get_publication_matched_status(writer, &status), "publication matched status");
    if (status.current_count > 0) return true;
    if (vc_now_ms() >= deadline_ms) return false;
    dds_sleepfor(DDS_MSECS(1));
  }
}

bool vc_written_by(dds_entity_t reader, const dds_sample_info_t *info, const dds_guid_t *owner) {
  dds_builtintopic_endpoint_t *writer = dds_get_matched_publication_data(reader, info->publication_handle);
  if (writer == NULL) return false;
  const bool same = memcmp(writer->participant_key.v, owner->v, sizeof owner->v) == 0;
  dds_builtintopic_free_endpoint(writer);
  return same;
}

/* The participant of the writer of the alive DaemonInfo of `server_id` among the samples `reader` holds. */
static bool find_daemon(dds_entity_t reader, const char *server_id, dds_guid_t *out) {
  enum { kMax = 16 };
  void *samples[kMax] = {NULL};
  dds_sample_info_t infos[kMax];
  const dds_return_t n = dds_read(reader, samples, infos, kMax, kMax);
  vc_check(n, "read ispars/daemons");
  bool found = false;
  for (dds_return_t i = 0; i < n && !found; ++i) {
    const ispars_msg_DaemonInfo *info = samples[i];
    if (!infos[i].valid_data || infos[i].instance_state != DDS_ALIVE_INSTANCE_STATE) continue;
    if (strcmp(info->server_id, server_id) != 0) continue;
    dds_builtintopic_endpoint_t *writer = dds_get_matched_publication_data(reader, infos[i].publication_handle);
    if (writer == NULL) continue;
    *out = writer->participant_key;
    dds_builtintopic_free_endpoint(writer);
    found = true;
  }
  if (n > 0) vc_check(dds_return_loan(reader, samples, n), "return loan");
  return found;
}

bool vc_daemon_participant(dds_entity_t participant, const char *server_id, double deadline_ms, dds_guid_t *out) {
  dds_qos_t *qos = vc_state_qos();
  const dds_entity_t reader = vc_reader(participant, &ispars_msg_DaemonInfo_desc, "ispars/daemons", qos);
  dds_delete_qos(qos);
  bool found = false;
  while (!(found = find_daemon(reader, server_id, out)) && vc_now_ms() < deadline_ms) dds_sleepfor(DDS_MSECS(20));
  dds_delete(reader);
  return found;
}

void vc_json_string(const char *text) {
  putchar('"');
  for (const unsigned char *c = (const unsigned char *)text; *c != '\0'; ++c) {
    if (*c == '"' || *c == '\\') {
      printf("\\%c", *c);
    } else if (*c < 0x20) {
      printf("\\u%04x", *c);
    } else {
      putchar(*c);
    }
  }
  putchar('"');
}
