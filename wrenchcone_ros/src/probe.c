// Copyright 2026 wrenchcone_ros developers
// SPDX-License-Identifier: MIT
/* wrenchcone_probe: check_wrench round trips measured from a compiled rcl client.
 *
 * A controller that asks the node whether a wrench is consistent is usually compiled
 * (C++, ros2_control). This program is such a client, with nothing of Python on its side:
 * it calls the node's check_wrench service at a fixed rate from one thread that waits
 * in rcl_wait, and writes one line per call. With --trigger it alternates each call with
 * a call to an std_srvs/Trigger service (e.g. an empty one in its own process): the floor
 * of any service call on the machine at that moment, measured by the same client.
 *
 *   wrenchcone_probe --mode MODE [--service NAME] [--trigger NAME] [--wrench FX,FY,TZ]
 *                    [--rate HZ] [--seconds S] [--timeout S] [--out FILE]
 *                    [--wait-for-signal] [--ros-args ...]
 *
 * Output (FILE, or standard output): a header line, then one line per call:
 *   kind sent_ns round_trip_ns status consistent pose_stamp_ns inputs_version
 * kind is "check" or "trigger"; sent_ns is CLOCK_REALTIME when the request was sent (the
 * clock of ROS stamps, to compare with the poses' stamps); round_trip_ns is
 * CLOCK_MONOTONIC from just before rcl_send_request to just after rcl_take_response;
 * status, consistent, pose_stamp_ns and inputs_version come from the reply (-1 for a
 * Trigger). A call unanswered within --timeout has round_trip_ns -1 and the rest -1.
 * "ready" goes to standard error when the services are found (the calls start then,
 * or at SIGUSR1 with --wait-for-signal), a summary when it ends (the counts, and each
 * kind's round trip p50 / p99 / max, nearest rank): after --seconds, or at SIGINT /
 * SIGTERM (the call in flight is completed). Exit status: 0 when every call
 * was answered, 1 otherwise, 2 on bad arguments or when a service never appears.
 *
 * docs/node.md, "Live use under load", says what it measured.
 */

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <rcl/client.h>
#include <rcl/error_handling.h>
#include <rcl/graph.h>
#include <rcl/init.h>
#include <rcl/node.h>
#include <rcl/wait.h>
#include <rosidl_runtime_c/string_functions.h>
#include <std_srvs/srv/trigger.h>

#include "wrenchcone_msgs/srv/check_wrench.h"

static volatile sig_atomic_t interrupted = 0, started = 0;

static void on_signal(int sig)
{
  if (sig == SIGUSR1) {
    started = 1;
  } else {
    interrupted = 1;
  }
}

static int64_t clock_ns(clockid_t id)
{
  struct timespec ts;
  clock_gettime(id, &ts);
  return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* The return code of a clean-up call that can only fail when we are ending anyway */
static void ignore(rcl_ret_t ret)
{
  (void)ret;
  rcl_reset_error();
}

/* Round trips (ns) of one kind of call, for the summary. */
typedef struct
{
  int64_t * ns;
  size_t n, cap;
} Samples;

static void add_sample(Samples * s, int64_t ns)
{
  if (s->n == s->cap) {
    size_t cap = s->cap ? 2 * s->cap : 1024;
    int64_t * grown = realloc(s->ns, cap * sizeof(int64_t));
    if (grown == NULL) {
      return;  /* the summary then leaves this one out; the line is written anyway */
    }
    s->ns = grown;
    s->cap = cap;
  }
  s->ns[s->n++] = ns;
}

static int by_value(const void * a, const void * b)
{
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

/* "name: n answered, round trip p50 / p99 / max X / Y / Z ms" (nearest-rank
 * percentiles: the ceil(n q)-th smallest) */
static void summarize(const char * name, Samples * s)
{
  if (s->n == 0) {
    return;
  }
  qsort(s->ns, s->n, sizeof(int64_t), by_value);
  size_t p50 = (s->n * 50 + 99) / 100, p99 = (s->n * 99 + 99) / 100;
  fprintf(
    stderr, "wrenchcone_probe: %s: %zu answered, round trip p50 / p99 / max "
    "%.3f / %.3f / %.3f ms\n", name, s->n, s->ns[p50 - 1] * 1e-6,
    s->ns[p99 - 1] * 1e-6, s->ns[s->n - 1] * 1e-6);
}

static void sleep_until(int64_t t_monotonic_ns)
{
  struct timespec ts = {t_monotonic_ns / 1000000000LL, t_monotonic_ns % 1000000000LL};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR &&
    !interrupted)
  {
  }
}

#define USAGE \
  "usage: wrenchcone_probe --mode MODE [--service NAME] [--trigger NAME]" \
  " [--wrench FX,FY,TZ] [--rate HZ] [--seconds S] [--timeout S] [--out FILE]" \
  " [--wait-for-signal] [--ros-args ...]\n" \
  "  --mode     the contact mode to check (one letter per fixel)\n" \
  "  --service  the check_wrench service (default wrenchcone/check_wrench)\n" \
  "  --trigger  an std_srvs/Trigger service called before each check (the floor)\n" \
  "  --wrench   fx,fy,tz in N, N, N m (default 0,1,0)\n" \
  "  --rate     calls per second of each kind (default 100)\n" \
  "  --seconds  how long to call (default 10; SIGINT ends it earlier)\n" \
  "  --timeout  seconds to wait for a service to appear, and for one reply (default 30)\n" \
  "  --out      write the lines to this file (default standard output)\n" \
  "  --wait-for-signal  after \"ready\", wait for SIGUSR1 before the first call\n"

/* The options that take one positive number. */
static int is_number_option(const char * a)
{
  return strcmp(a, "--rate") == 0 || strcmp(a, "--seconds") == 0 ||
         strcmp(a, "--timeout") == 0;
}

static int usage(const char * why)
{
  fprintf(stderr, "wrenchcone_probe: %s\n" USAGE, why);
  return 2;
}

/* Wait until `client`'s reply to `seq` arrives (taking it into `response`), or until
 * `timeout_ns`. Returns 1 when taken, 0 on timeout, -1 on an rcl error. */
static int await_reply(
  rcl_wait_set_t * ws, rcl_client_t * client, int64_t seq,
  void * response, int64_t timeout_ns)
{
  int64_t deadline = clock_ns(CLOCK_MONOTONIC) + timeout_ns;
  for (;; ) {
    rmw_service_info_t info;
    rcl_ret_t ret = rcl_take_response_with_info(client, &info, response);
    if (ret == RCL_RET_OK) {
      if (info.request_id.sequence_number == seq) {
        return 1;
      }
      continue;  /* a late reply to an earlier call that timed out */
    }
    if (ret != RCL_RET_CLIENT_TAKE_FAILED) {
      fprintf(
        stderr, "wrenchcone_probe: taking a reply failed: %s\n",
        rcl_get_error_string().str);
      rcl_reset_error();
      return -1;
    }
    int64_t left = deadline - clock_ns(CLOCK_MONOTONIC);
    if (left <= 0) {
      return 0;
    }
    if (rcl_wait_set_clear(ws) != RCL_RET_OK ||
      rcl_wait_set_add_client(ws, client, NULL) != RCL_RET_OK)
    {
      rcl_reset_error();
      return -1;
    }
    ret = rcl_wait(ws, left);
    if (ret != RCL_RET_OK && ret != RCL_RET_TIMEOUT) {
      rcl_reset_error();
      return -1;
    }
  }
}

static int wait_for_server(rcl_node_t * node, rcl_client_t * client, double seconds)
{
  int64_t deadline = clock_ns(CLOCK_MONOTONIC) + (int64_t)(seconds * 1e9);
  while (clock_ns(CLOCK_MONOTONIC) < deadline) {
    bool available = false;
    if (rcl_service_server_is_available(node, client, &available) == RCL_RET_OK &&
      available)
    {
      return 1;
    }
    rcl_reset_error();
    struct timespec ts = {0, 50000000};
    nanosleep(&ts, NULL);
  }
  fprintf(
    stderr, "wrenchcone_probe: the service %s did not appear within %g s\n",
    rcl_client_get_service_name(client), seconds);
  return 0;
}

int main(int argc, char ** argv)
{
  const char * mode = NULL, * service = "wrenchcone/check_wrench", * trigger = NULL;
  const char * out_path = NULL;
  double fx = 0.0, fy = 1.0, tz = 0.0, rate = 100.0, seconds = 10.0, timeout = 30.0;
  int ros_args_at = argc, wait_for_signal = 0;
  for (int i = 1; i < argc; ++i) {
    const char * a = argv[i];
    if (strcmp(a, "--ros-args") == 0) {
      ros_args_at = i;
      break;
    }
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      printf(
        "wrenchcone_probe: calls check_wrench at a fixed rate from a compiled client "
        "and prints each round trip\n" USAGE);
      return 0;
    }
    if (strcmp(a, "--wait-for-signal") == 0) {
      wait_for_signal = 1;
      continue;
    }
    if (i + 1 >= argc) {
      return usage("every option but --wait-for-signal takes a value");
    }
    const char * v = argv[++i];
    char * end = NULL;
    if (strcmp(a, "--mode") == 0) {
      mode = v;
    } else if (strcmp(a, "--service") == 0) {
      service = v;
    } else if (strcmp(a, "--trigger") == 0) {
      trigger = v;
    } else if (strcmp(a, "--out") == 0) {
      out_path = v;
    } else if (strcmp(a, "--wrench") == 0) {
      if (sscanf(v, "%lf,%lf,%lf", &fx, &fy, &tz) != 3 ||
        !isfinite(fx) || !isfinite(fy) || !isfinite(tz))
      {
        return usage("--wrench takes three finite numbers FX,FY,TZ (N, N, N m)");
      }
    } else if (is_number_option(a)) {
      double x = strtod(v, &end);
      if (end == v || *end != '\0' || !isfinite(x) || x <= 0.0) {
        fprintf(stderr, "wrenchcone_probe: %s takes a positive number, not '%s'\n", a, v);
        return 2;
      }
      *(strcmp(a, "--rate") == 0 ? &rate : strcmp(a, "--seconds") == 0 ? &seconds :
      &timeout) = x;
    } else {
      fprintf(stderr, "wrenchcone_probe: unknown option '%s'\n", a);
      return usage("see the options below");
    }
  }
  if (mode == NULL) {
    return usage("--mode is required");
  }
  FILE * out = stdout;
  if (out_path != NULL && (out = fopen(out_path, "w")) == NULL) {
    fprintf(stderr, "wrenchcone_probe: cannot write %s: %s\n", out_path, strerror(errno));
    return 2;
  }

  /* rcl sees the program name and what follows --ros-args */
  int rcl_argc = 1 + (argc - ros_args_at);
  const char ** rcl_argv = calloc((size_t)rcl_argc, sizeof(char *));
  rcl_argv[0] = argv[0];
  for (int i = ros_args_at; i < argc; ++i) {
    rcl_argv[1 + i - ros_args_at] = argv[i];
  }
  rcl_allocator_t alloc = rcl_get_default_allocator();
  rcl_init_options_t init_options = rcl_get_zero_initialized_init_options();
  rcl_context_t context = rcl_get_zero_initialized_context();
  rcl_node_t node = rcl_get_zero_initialized_node();
  rcl_node_options_t node_options = rcl_node_get_default_options();
  if (rcl_init_options_init(&init_options, alloc) != RCL_RET_OK ||
    rcl_init(rcl_argc, rcl_argv, &init_options, &context) != RCL_RET_OK ||
    rcl_node_init(&node, "wrenchcone_probe", "", &context, &node_options) != RCL_RET_OK)
  {
    fprintf(
      stderr, "wrenchcone_probe: starting rcl failed: %s\n",
      rcl_get_error_string().str);
    return 2;
  }
  rcl_client_options_t client_options = rcl_client_get_default_options();
  rcl_client_t check = rcl_get_zero_initialized_client();
  rcl_client_t empty = rcl_get_zero_initialized_client();
  if (rcl_client_init(
      &check, &node, ROSIDL_GET_SRV_TYPE_SUPPORT(
        wrenchcone_msgs, srv,
        CheckWrench),
      service, &client_options) != RCL_RET_OK ||
    (trigger != NULL &&
    rcl_client_init(
      &empty, &node, ROSIDL_GET_SRV_TYPE_SUPPORT(std_srvs, srv, Trigger),
      trigger, &client_options) != RCL_RET_OK))
  {
    fprintf(stderr, "wrenchcone_probe: a client failed: %s\n", rcl_get_error_string().str);
    return 2;
  }
  if (!wait_for_server(&node, &check, timeout) ||
    (trigger != NULL && !wait_for_server(&node, &empty, timeout)))
  {
    return 2;
  }
  /* SIGUSR1 stays blocked except inside sigsuspend: one sent right after "ready" is
   * not lost */
  sigset_t usr1, unblocked;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  sigprocmask(SIG_BLOCK, &usr1, &unblocked);
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  signal(SIGUSR1, on_signal);
  fprintf(
    out, "kind sent_ns round_trip_ns status consistent pose_stamp_ns "
    "inputs_version\n");
  fflush(out);
  fprintf(stderr, "ready\n");
  while (wait_for_signal && !started && !interrupted) {
    sigsuspend(&unblocked);
  }
  rcl_wait_set_t ws = rcl_get_zero_initialized_wait_set();
  if (rcl_wait_set_init(&ws, 0, 0, 0, 1, 0, 0, &context, alloc) != RCL_RET_OK) {
    fprintf(stderr, "wrenchcone_probe: a wait set failed: %s\n", rcl_get_error_string().str);
    return 2;
  }

  wrenchcone_msgs__srv__CheckWrench_Request request;
  wrenchcone_msgs__srv__CheckWrench_Response response;
  std_srvs__srv__Trigger_Request t_request;
  std_srvs__srv__Trigger_Response t_response;
  wrenchcone_msgs__srv__CheckWrench_Request__init(&request);
  wrenchcone_msgs__srv__CheckWrench_Response__init(&response);
  std_srvs__srv__Trigger_Request__init(&t_request);
  std_srvs__srv__Trigger_Response__init(&t_response);
  rosidl_runtime_c__String__assign(&request.mode, mode);
  request.wrench.force.x = fx;
  request.wrench.force.y = fy;
  request.wrench.torque.z = tz;

  const int64_t period = (int64_t)(1e9 / rate);
  const int64_t timeout_ns = (int64_t)(timeout * 1e9);
  int64_t next = clock_ns(CLOCK_MONOTONIC);
  const int64_t end = next + (int64_t)(seconds * 1e9);
  int64_t calls = 0, unanswered = 0, errors = 0;
  Samples rtts[2] = {{NULL, 0, 0}, {NULL, 0, 0}};  /* trigger, check */
  while (next < end && errors == 0 && !interrupted) {
    for (int k = trigger != NULL ? 0 : 1; k < 2; ++k) {
      rcl_client_t * client = k == 0 ? &empty : &check;
      void * req = k == 0 ? (void *)&t_request : (void *)&request;
      void * resp = k == 0 ? (void *)&t_response : (void *)&response;
      int64_t seq = 0;
      int64_t sent = clock_ns(CLOCK_REALTIME);
      int64_t t0 = clock_ns(CLOCK_MONOTONIC);
      if (rcl_send_request(client, req, &seq) != RCL_RET_OK) {
        fprintf(
          stderr, "wrenchcone_probe: sending failed: %s\n",
          rcl_get_error_string().str);
        rcl_reset_error();
        ++errors;
        break;
      }
      int got = await_reply(&ws, client, seq, resp, timeout_ns);
      int64_t rtt = clock_ns(CLOCK_MONOTONIC) - t0;
      ++calls;
      if (got < 0) {
        ++errors;
        break;
      }
      if (got == 1) {
        add_sample(&rtts[k], rtt);
      }
      if (got == 0) {
        ++unanswered;
        fprintf(out, "%s %" PRId64 " -1 -1 -1 -1 -1\n", k == 0 ? "trigger" : "check", sent);
      } else if (k == 0) {
        fprintf(out, "trigger %" PRId64 " %" PRId64 " -1 -1 -1 -1\n", sent, rtt);
      } else {
        int64_t stamp = (int64_t)response.pose_stamp.sec * 1000000000LL +
          response.pose_stamp.nanosec;
        fprintf(
          out, "check %" PRId64 " %" PRId64 " %d %d %" PRId64 " %" PRIu64 "\n", sent,
          rtt, (int)response.status, (int)response.consistent, stamp,
          response.inputs_version);
      }
    }
    next += period;
    int64_t now = clock_ns(CLOCK_MONOTONIC);
    if (next < now) {
      next = now;  /* behind: the next call at once, no burst to catch up */
    }
    sleep_until(next);
  }
  fprintf(
    stderr, "wrenchcone_probe: %" PRId64 " calls, %" PRId64 " unanswered, %" PRId64 " errors\n",
    calls,
    unanswered, errors);
  summarize("check_wrench", &rtts[1]);
  summarize("trigger", &rtts[0]);
  free(rtts[0].ns);
  free(rtts[1].ns);
  if (out != stdout) {
    fclose(out);
  }
  wrenchcone_msgs__srv__CheckWrench_Request__fini(&request);
  wrenchcone_msgs__srv__CheckWrench_Response__fini(&response);
  std_srvs__srv__Trigger_Request__fini(&t_request);
  std_srvs__srv__Trigger_Response__fini(&t_response);
  ignore(rcl_wait_set_fini(&ws));
  ignore(rcl_client_fini(&check, &node));
  if (trigger != NULL) {
    ignore(rcl_client_fini(&empty, &node));
  }
  ignore(rcl_node_fini(&node));
  ignore(rcl_shutdown(&context));
  ignore(rcl_context_fini(&context));
  ignore(rcl_init_options_fini(&init_options));
  free(rcl_argv);
  return unanswered == 0 && errors == 0 ? 0 : 1;
}
