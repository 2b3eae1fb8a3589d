/* What a late joiner reads without asking: a scene's latest status and the roadmap updates kept for
 * it (transient-local), each believed only when its writer belongs to the participant announcing
 * the daemon it names. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include "vendor_client.h"

enum { kWaitMs = 30000, kPollMs = 10 };

void vc_json_status(const ispars_msg_SceneStatus *s) {
  printf("\"scene\":");
  vc_json_string(s->scene);
  printf(",\"status_server_id\":");
  vc_json_string(s->server_id);
  printf(",\"status_seq\":%llu,\"state\":%d,\"method\":", (unsigned long long)s->status_seq, (int)s->state);
  vc_json_string(s->method);
  printf(",\"generation\":%llu,\"samples_done\":%llu,\"version\":%llu,\"vertices\":%u,\"edges\":%u,\"components\":%u,"
         "\"poi_count\":%u,\"pois_covered\":%u",
         (unsigned long long)s->generation, (unsigned long long)s->samples_done, (unsigned long long)s->version,
         s->vertices, s->edges, s->components, s->poi_count, s->pois_covered);
}

/* The latest status of `scene` held by `reader`, when its daemon's participant wrote it. */
static bool read_status(dds_entity_t reader, const char *scene, ispars_msg_SceneStatus *out, dds_guid_t *daemon) {
  ispars_msg_SceneStatus key;
  memset(&key, 0, sizeof key);
  snprintf(key.scene, sizeof key.scene, "%s", scene);
  const dds_instance_handle_t instance = dds_lookup_instance(reader, &key);
  if (instance == DDS_HANDLE_NIL) return false;
  memset(out, 0, sizeof *out);
  void *sample = out;
  dds_sample_info_t info;
  const dds_return_t n = dds_read_instance(reader, &sample, &info, 1, 1, instance);
  if (n == DDS_RETCODE_PRECONDITION_NOT_MET || n == DDS_RETCODE_BAD_PARAMETER) return false; /* gone meanwhile */
  vc_check(n, "read ispars/status");
  const dds_entity_t participant = dds_get_participant(reader);
  if (n == 1 && info.valid_data && vc_daemon_participant(participant, out->server_id, vc_now_ms() + 1000, daemon) &&
      vc_written_by(reader, &info, daemon)) {
    return true;
  }
  dds_sample_free(out, &ispars_msg_SceneStatus_desc, DDS_FREE_CONTENTS);
  return false;
}

/* Waits for the status of `scene` (see read_status); exits at the deadline. */
static void latest_status(dds_entity_t participant, const char *scene, ispars_msg_SceneStatus *out,
                          dds_guid_t *daemon) {
  dds_qos_t *qos = vc_state_qos();
  const dds_entity_t reader = vc_reader(participant, &ispars_msg_SceneStatus_desc, "ispars/status", qos);
  dds_delete_qos(qos);
  const double deadline = vc_now_ms() + kWaitMs;
  while (!read_status(reader, scene, out, daemon)) {
    if (vc_now_ms() >= deadline) vc_fail("no status of scene '%s' from its daemon within %d ms", scene, kWaitMs);
    dds_sleepfor(DDS_MSECS(kPollMs));
  }
  dds_delete(reader);
}

int vc_cmd_status(int domain, const char *scene) {
  char prefix[25];
  const dds_entity_t participant = vc_participant(domain, prefix);
  ispars_msg_SceneStatus status;
  dds_guid_t daemon;
  latest_status(participant, scene, &status, &daemon);
  printf("{");
  vc_json_status(&status);
  printf(",\"last_error\":");
  vc_json_string(status.last_error != NULL ? status.last_error : "");
  puts("}");
  dds_sample_free(&status, &ispars_msg_SceneStatus_desc, DDS_FREE_CONTENTS);
  vc_check(dds_delete(participant), "delete participant");
  return 0;
}

/* The batches of one roadmap generation, chained by version from 0. */
typedef struct chain {
  uint64_t generation;
  uint64_t next_version;
  unsigned batches;
  unsigned long long vertices, edges;
} chain;

/* Adds one batch to `c`: false (after a message) when it leaves a gap. */
static bool add_batch(chain *c, const ispars_msg_UpdateBatch *b) {
  if (b->generation != c->generation || b->to_version <= c->next_version) return true; /* other, or old or a mark */
  if (b->from_version != c->next_version) {
    fprintf(stderr, "ispars-cyclone: updates of generation %llu: a batch %llu..%llu after version %llu (a gap)\n",
            (unsigned long long)c->generation, (unsigned long long)b->from_version,
            (unsigned long long)b->to_version, (unsigned long long)c->next_version);
    return false;
  }
  c->next_version = b->to_version;
  ++c->batches;
  c->vertices += b->vertices._length;
  c->edges += b->edges._length;
  return true;
}

/* Takes every batch `reader` holds into `c`: false on a gap. */
static bool take_batches(dds_entity_t reader, const char *scene, const dds_guid_t *daemon, chain *c) {
  for (;;) {
    ispars_msg_UpdateBatch batch;
    memset(&batch, 0, sizeof batch);
    void *sample = &batch;
    dds_sample_info_t info;
    const dds_return_t n = dds_take(reader, &sample, &info, 1, 1);
    vc_check(n, "take ispars/updates");
    if (n == 0) return true;
    bool fine = true;
    if (info.valid_data && strcmp(batch.scene, scene) == 0 && vc_written_by(reader, &info, daemon)) {
      fine = add_batch(c, &batch);
    }
    dds_sample_free(&batch, &ispars_msg_UpdateBatch_desc, DDS_FREE_CONTENTS);
    if (!fine) return false;
  }
}

int vc_cmd_updates(int domain, const char *scene) {
  char prefix[25];
  const dds_entity_t participant = vc_participant(domain, prefix);
  dds_qos_t *qos = vc_updates_qos();
  const dds_entity_t reader = vc_reader(participant, &ispars_msg_UpdateBatch_desc, "ispars/updates", qos);
  dds_delete_qos(qos);
  ispars_msg_SceneStatus status;
  dds_guid_t daemon;
  latest_status(participant, scene, &status, &daemon);
  chain c = {status.generation, 0, 0, 0, 0};
  const double deadline = vc_now_ms() + kWaitMs;
  while (c.next_version < status.version) {
    if (!take_batches(reader, scene, &daemon, &c)) vc_fail("the updates of '%s' do not start at version 0", scene);
    if (c.next_version >= status.version) break;
    if (vc_now_ms() >= deadline) {
      vc_fail("updates of '%s' reached version %llu of %llu within %d ms", scene, (unsigned long long)c.next_version,
              (unsigned long long)status.version, kWaitMs);
    }
    dds_sleepfor(DDS_MSECS(kPollMs));
  }
  printf("{\"scene\":");
  vc_json_string(scene);
  printf(",\"generation\":%llu,\"status_version\":%llu,\"version\":%llu,\"batches\":%u,\"vertices\":%llu,"
         "\"edges\":%llu}\n",
         (unsigned long long)c.generation, (unsigned long long)status.version, (unsigned long long)c.next_version,
         c.batches, c.vertices, c.edges);
  dds_sample_free(&status, &ispars_msg_SceneStatus_desc, DDS_FREE_CONTENTS);
  vc_check(dds_delete(participant), "delete participant");
  return 0;
}
