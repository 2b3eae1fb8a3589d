/* ispars-cyclone: a client of isparsd written with Eclipse Cyclone DDS (C API), for the
 * integration tests (tests/integration/test_service_vendor.cpp). Each command prints one JSON
 * object on stdout and exits 0, or prints a message on stderr and exits nonzero. Every wait is
 * bounded.
 *
 *   ispars-cyclone DOMAIN status SCENE               the scene's latest status, as a late joiner
 *   ispars-cyclone DOMAIN updates SCENE              update batches up to the status's version
 *   ispars-cyclone DOMAIN stats SERVER SCENE         one STATS query
 *   ispars-cyclone DOMAIN tour SERVER SCENE BUDGET   one TOUR with its progress
 *   ispars-cyclone DOMAIN fresh N SERVER SCENE       N new participants in a row, one STATS each */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vendor_client.h"

static long number(const char *text, const char *what, long low, long high) {
  char *end = NULL;
  const long value = strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < low || value > high) vc_fail("%s: '%s' is not in %ld..%ld", what, text, low, high);
  return value;
}

static double seconds(const char *text) {
  char *end = NULL;
  const double value = strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0 && value <= 3600.0)) vc_fail("budget: '%s' is not in (0, 3600]", text);
  return value;
}

static void usage(void) {
  fputs("usage: ispars-cyclone DOMAIN status SCENE | updates SCENE | stats SERVER SCENE | tour SERVER SCENE BUDGET\n"
        "                            | fresh N SERVER SCENE\n",
        stderr);
  exit(2);
}

int main(int argc, char **argv) {
  if (argc < 4) usage();
  const int domain = (int)number(argv[1], "domain", 0, 232);
  const char *command = argv[2];
  vc_configure();
  setvbuf(stdout, NULL, _IOLBF, 0);
  if (strcmp(command, "status") == 0 && argc == 4) return vc_cmd_status(domain, argv[3]);
  if (strcmp(command, "updates") == 0 && argc == 4) return vc_cmd_updates(domain, argv[3]);
  if (strcmp(command, "stats") == 0 && argc == 5) return vc_cmd_stats(domain, argv[3], argv[4]);
  if (strcmp(command, "tour") == 0 && argc == 6) return vc_cmd_tour(domain, argv[3], argv[4], seconds(argv[5]));
  if (strcmp(command, "fresh") == 0 && argc == 6) {
    return vc_cmd_fresh(domain, (int)number(argv[3], "N", 1, 100000), argv[4], argv[5]);
  }
  usage();
}
