/*
 * wrenchcone_ros.node._fastcheck: check_wrench answered without the Python interpreter.
 *
 * The node's publishing worker (Python) computes the cone of every monitored mode for
 * each new snapshot and hands it to a Lane (set_entries), as data: the cone's rows and
 * its margin geometry (lineality rows, unit rays, face projections: cones._Query's own
 * values), and the snapshot's verdicts as deadlines on the node clock (fresh until;
 * the receive stamp of the newest pose these cones may still answer for: the node's
 * pose_reuse_window, decided in Python). The Lane owns the node's `~/check_wrench` rcl
 * service and answers it in a thread of its own that never takes the GIL for a request
 * it can answer from those cones: a concrete monitored mode, a wrench planar as sent
 * (force.z, torque.x, torque.y exactly zero, its largest part within the bounds Python
 * gave: no rescaling needed), no classification, and both deadlines not passed. Every
 * other request is queued for the node's Python handler (services.py), whose own
 * thread takes it (next_forwarded), answers it as before and sends the reply (respond);
 * the service thread goes on meanwhile. It never runs Python code.
 *
 * Every pose message is taken through the Lane (take_pose), so the Lane always knows
 * when the newest pose was received; its receive stamps (node clock, ns) increase
 * strictly, so a stamp names one take.
 *
 * The membership test and margin are a line-by-line port of cones._Query.check (same
 * float operations in the same order on the same numbers, compiled with
 * -ffp-contract=off): consistent and margin are identical to the reference
 * (test/node/test_fastcheck.py). Tolerances, bounds and status codes come from Python
 * (tolerances.py, conversions.py, the srv), never here. Only the per-request
 * arithmetic is here: the dot products, the projections' products, the clock reads.
 *
 * Locking: one mutex guards the Lane's state (entries, poses, the queue, counters); the
 * service thread never takes the GIL, and a Python-facing method releases the GIL
 * before it takes the mutex.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <rcl/error_handling.h>
#include <rcl/guard_condition.h>
#include <rcl/node.h>
#include <rcl/service.h>
#include <rcl/subscription.h>
#include <rcl/time.h>
#include <rcl/wait.h>
#include <rmw/serialized_message.h>
#include <rosidl_runtime_c/string_functions.h>

#include "wrenchcone_msgs/srv/check_wrench.h"

typedef wrenchcone_msgs__srv__CheckWrench_Request Request;
typedef wrenchcone_msgs__srv__CheckWrench_Response Response;
typedef bool (*convert_from_py_t)(PyObject *, void *);

/* A request for the Python handler, queued by the service thread (next_forwarded). */
typedef struct Forward {
  rmw_request_id_t id;
  Request req;
  int responded;
  struct Forward * next;
} Forward;

static void free_forward(Forward * fw)
{
  wrenchcone_msgs__srv__CheckWrench_Request__fini(&fw->req);
  free(fw);
}

/* One monitored mode's cone, as cones._Query holds it (unit nondimensional rows); R and
 * P are _Query.rays and _Query.projections, computed in Python. */
typedef struct {
  char * mode;
  uint8_t status;     /* OK or MODE_INFEASIBLE */
  char * message;
  int feasible;
  double inv_l;       /* 1 / length scale (1/m) */
  Py_ssize_t nF, nE, nL, nR, nP;
  double * F, * E, * L, * R;  /* rows of 3 */
  double * P;                 /* nP 3x3 projections, row-major */
} Entry;

typedef struct {
  PyObject_HEAD
  pthread_mutex_t mu;
  rcl_clock_t * clock;
  double cone_tol, smallest, largest;  /* the wrench's largest part: in [smallest, largest] or 0 */
  uint8_t st_ok, st_infeasible, st_internal, st_limit;
  /* poses */
  rcl_subscription_t * sub;
  rcl_guard_condition_t * wake;      /* the publishing worker's guard condition */
  rcl_serialized_message_t pose, scratch;
  int have_pose;                     /* a taken pose waits in `pose` */
  int64_t pose_ns;                   /* its receive stamp */
  int64_t newest_ns;                 /* receive stamp of the newest pose taken; -1 none */
  /* the snapshot of the entries */
  uint64_t generation;               /* clear() increments; set_entries must match */
  Entry * entries;
  Py_ssize_t n_entries;
  uint64_t version;
  char * frame_id;
  int32_t pose_sec, fixels_sec;
  uint32_t pose_nsec, fixels_nsec;
  int64_t oldest_ns;       /* receive stamp of the snapshot's oldest received input; -1 none */
  int64_t pose_until_ns;   /* newest pose receive stamp these entries may answer for */
  int64_t fresh_until_ns;  /* last node-clock instant at which the inputs are fresh */
  /* the service */
  rcl_node_t * node;
  rcl_service_t service;
  rcl_guard_condition_t stop;
  int serving, stopping, thread_ended;
  int accepting;                     /* respond() may still send (the service exists) */
  Forward * head, * tail;            /* requests for the Python handler */
  Py_ssize_t queued, max_queued;     /* how many wait; more are refused at once */
  pthread_cond_t queued_cv;
  pthread_t thread;
  convert_from_py_t convert;
  /* counters */
  uint64_t n_fast, n_forwarded, n_failed;
  uint64_t n_poses_in_service;       /* pose takes that the service thread made */
  uint64_t n_refused_full;           /* refused: max_queued were waiting */
  uint64_t n_fast_status[16];
} Lane;

/* --- helpers --------------------------------------------------------------------- */
/* A cleanup or wake-up call whose failure changes nothing: forget its error. */
static void ignore(rcl_ret_t ret)
{
  (void)ret;
  rcl_reset_error();
}

static char * dup_str(const char * s, Py_ssize_t n)
{
  char * out = malloc((size_t)n + 1);
  if (out) {
    memcpy(out, s, (size_t)n);
    out[n] = '\0';
  }
  return out;
}

static void free_entry(Entry * e)
{
  free(e->mode); free(e->message);
  free(e->F); free(e->E); free(e->L); free(e->R); free(e->P);
  memset(e, 0, sizeof(*e));
}

static void free_entries(Entry * entries, Py_ssize_t n)
{
  for (Py_ssize_t i = 0; i < n; ++i) {
    free_entry(&entries[i]);
  }
  free(entries);
}

static int64_t now_ns(Lane * self)
{
  rcl_time_point_value_t t = 0;
  if (rcl_clock_get_now(self->clock, &t) != RCL_RET_OK) {
    rcl_reset_error();
  }
  return (int64_t)t;
}

static double dot3(const double * r, double x, double y, double z)
{
  return r[0] * x + r[1] * y + r[2] * z;
}

/* (k, 3) float64 C-contiguous buffer -> malloc'ed copy; *n = k. 0 on success. */
static int rows_of(PyObject * obj, const char * what, double ** out, Py_ssize_t * n)
{
  Py_buffer view;
  if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
    return -1;
  }
  int bad = view.ndim != 2 || view.shape[1] != 3 || view.itemsize != 8 ||
    view.format == NULL || strcmp(view.format, "d") != 0;
  if (bad) {
    PyBuffer_Release(&view);
    PyErr_Format(PyExc_ValueError, "%s must be a C-contiguous float64 (k, 3) array", what);
    return -1;
  }
  *n = view.shape[0];
  *out = malloc(sizeof(double) * (size_t)(3 * *n + 1));
  if (*out == NULL) {
    PyBuffer_Release(&view);
    PyErr_NoMemory();
    return -1;
  }
  memcpy(*out, view.buf, sizeof(double) * (size_t)(3 * *n));
  PyBuffer_Release(&view);
  return 0;
}

static int in_cone(const Entry * e, const double * p, double tol)
{
  double bound = tol * sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  for (Py_ssize_t k = 0; k < e->nF; ++k) {
    if (dot3(e->F + 3 * k, p[0], p[1], p[2]) > bound) {
      return 0;
    }
  }
  for (Py_ssize_t k = 0; k < e->nE; ++k) {
    if (fabs(dot3(e->E + 3 * k, p[0], p[1], p[2])) > bound) {
      return 0;
    }
  }
  return 1;
}

/* cones._Query.check for g = (fx N, fy N, tz N m): 0 ok, -1 when g is not finite. */
static int check(const Entry * e, double tol, const double g[3], int * contains,
                 double * margin)
{
  if (!e->feasible) {
    *contains = 0; *margin = -1.0;
    return 0;
  }
  double x = g[0], y = g[1], z = g[2] * e->inv_l;
  double norm = sqrt(x * x + y * y + z * z);
  if (!isfinite(norm)) {
    return -1;
  }
  if (norm == 0) {
    *contains = 1; *margin = 0.0;
    return 0;
  }
  x = x / norm; y = y / norm; z = z / norm;
  if (e->nF == 0 && e->nE == 0) {
    *contains = 1; *margin = 1.0;
    return 0;
  }
  double fmax = -INFINITY;
  for (Py_ssize_t k = 0; k < e->nF; ++k) {
    double v = dot3(e->F + 3 * k, x, y, z);
    if (k == 0 || v > fmax) {
      fmax = v;
    }
  }
  double emax = 0.0;
  for (Py_ssize_t k = 0; k < e->nE; ++k) {
    double v = fabs(dot3(e->E + 3 * k, x, y, z));
    if (k == 0 || v > emax) {
      emax = v;
    }
  }
  *contains = fmax <= tol && emax <= tol;
  if (fmax <= 0.0 && emax == 0.0) {
    *margin = e->nE ? 0.0 : -fmax;
    return 0;
  }
  double lin2 = 0.0;
  for (Py_ssize_t k = 0; k < e->nL; ++k) {
    lin2 = k == 0 ? pow(dot3(e->L, x, y, z), 2.0)
                  : lin2 + pow(dot3(e->L + 3 * k, x, y, z), 2.0);
  }
  double best2 = 1.0 - lin2;
  double t = 0.0;
  for (Py_ssize_t k = 0; k < e->nR; ++k) {
    double v = dot3(e->R + 3 * k, x, y, z);
    if (k == 0 || v > t) {
      t = v;
    }
  }
  if (t > 0) {
    double v = 1.0 - lin2 - t * t;
    if (v < best2) {
      best2 = v;
    }
  }
  for (Py_ssize_t k = 0; k < e->nP; ++k) {
    const double * P = e->P + 9 * k;
    double p[3] = {dot3(P, x, y, z), dot3(P + 3, x, y, z), dot3(P + 6, x, y, z)};
    if (in_cone(e, p, tol)) {
      double dx = x - p[0], dy = y - p[1], dz = z - p[2];
      double v = dx * dx + dy * dy + dz * dz;
      if (v < best2) {
        best2 = v;
      }
    }
  }
  *margin = -sqrt(0.0 > best2 ? 0.0 : best2);
  return 0;
}

static const Entry * find_entry(const Lane * self, const char * mode, size_t n)
{
  for (Py_ssize_t i = 0; i < self->n_entries; ++i) {
    const char * m = self->entries[i].mode;
    if (strlen(m) == n && memcmp(m, mode, n) == 0) {
      return &self->entries[i];
    }
  }
  return NULL;
}

/* Take every waiting pose message (lock held), keep the newest; 1 if one was taken. */
static int drain_poses(Lane * self)
{
  if (self->sub == NULL) {
    return 0;
  }
  int took = 0;
  for (;;) {
    rmw_message_info_t info = rmw_get_zero_initialized_message_info();
    rcl_ret_t ret = rcl_take_serialized_message(self->sub, &self->scratch, &info, NULL);
    if (ret != RCL_RET_OK) {
      rcl_reset_error();
      break;
    }
    rcl_serialized_message_t tmp = self->pose;
    self->pose = self->scratch;
    self->scratch = tmp;
    took = 1;
  }
  if (took) {
    int64_t t = now_ns(self);
    if (self->newest_ns >= 0 && t <= self->newest_ns) {
      t = self->newest_ns + 1;  /* strictly increasing: a stamp names one take */
    }
    self->have_pose = 1;
    self->pose_ns = self->newest_ns = t;
  }
  return took;
}

/* --- the service thread ------------------------------------------------------------ */
static int set_string(rosidl_runtime_c__String * s, const char * value)
{
  return rosidl_runtime_c__String__assign(s, value ? value : "") ? 0 : -1;
}

/* Whether the entries may answer now (lock held), by the deadlines Python handed over:
 * no pose taken after pose_until_ns, the inputs fresh until fresh_until_ns. *age: the
 * age (s) of the oldest received input, as freshness.freshness computes it. */
static int usable(const Lane * self, int64_t now, double * age)
{
  if (self->newest_ns > self->pose_until_ns || now > self->fresh_until_ns) {
    return 0;  /* a newer pose, or stale: the Python handler answers */
  }
  *age = 0.0;
  if (self->oldest_ns >= 0) {
    double a = (double)(now - self->oldest_ns) * 1e-9;
    *age = a > 0.0 ? a : 0.0;
  }
  return 1;
}

/* Answer from the entries if allowed (lock held): 1 answered, 0 forward. */
static int answer_fast(Lane * self, const Request * req, Response * resp)
{
  if (req->classify || self->n_entries == 0) {
    return 0;
  }
  const Entry * e = find_entry(self, req->mode.data, req->mode.size);
  if (e == NULL) {
    return 0;
  }
  const geometry_msgs__msg__Vector3 * f = &req->wrench.force, * m = &req->wrench.torque;
  if (f->z != 0.0 || m->x != 0.0 || m->y != 0.0 ||
      !isfinite(f->x) || !isfinite(f->y) || !isfinite(m->z)) {
    return 0;  /* out of plane or not finite: the Python handler says why */
  }
  double big = fmax(fabs(f->x), fmax(fabs(f->y), fabs(m->z)));
  if (big > self->largest || (big > 0.0 && big < self->smallest)) {
    return 0;  /* conversions.wrench_to_planar rescales it */
  }
  double age = 0.0;
  if (!usable(self, now_ns(self), &age)) {
    return 0;
  }
  int contains = 0;
  double margin = -1.0;
  if (e->status == self->st_ok) {
    double g[3] = {f->x, f->y, m->z};
    if (check(e, self->cone_tol, g, &contains, &margin) != 0) {
      return 0;
    }
  }
  resp->consistent = contains;
  resp->margin = margin;
  resp->status = e->status;
  resp->only_mode = false;
  resp->inputs_version = self->version;
  resp->inputs_age = age;
  resp->pose_stamp.sec = self->pose_sec;  /* (0, 0) when the scene's own pose */
  resp->pose_stamp.nanosec = self->pose_nsec;
  resp->fixels_stamp.sec = self->fixels_sec;
  resp->fixels_stamp.nanosec = self->fixels_nsec;
  if (set_string(&resp->message, e->message) || set_string(&resp->frame_id, self->frame_id)) {
    return 0;
  }
  return 1;
}

static void serve_one(Lane * self, rmw_request_id_t * id, Request * req)
{
  Response resp;
  if (!wrenchcone_msgs__srv__CheckWrench_Response__init(&resp)) {
    return;
  }
  pthread_mutex_lock(&self->mu);
  int took = drain_poses(self);
  self->n_poses_in_service += (uint64_t)took;
  int fast = answer_fast(self, req, &resp);
  if (fast) {
    self->n_fast++;
    self->n_fast_status[resp.status & 15]++;
  }
  rcl_guard_condition_t * wake = self->wake;
  pthread_mutex_unlock(&self->mu);
  if (took && wake != NULL) {
    ignore(rcl_trigger_guard_condition(wake));  /* the worker: a new pose, taken here */
  }
  if (fast) {
    if (rcl_send_response(&self->service, id, &resp) != RCL_RET_OK) {
      rcl_reset_error();  /* the client is gone */
    }
  } else {  /* queue a copy for the Python handler's thread, if there is room */
    Forward * fw = calloc(1, sizeof(Forward));
    Py_ssize_t full = 0;
    if (fw != NULL && wrenchcone_msgs__srv__CheckWrench_Request__init(&fw->req) &&
        wrenchcone_msgs__srv__CheckWrench_Request__copy(req, &fw->req)) {
      fw->id = *id;
      pthread_mutex_lock(&self->mu);
      if (self->queued >= self->max_queued) {
        full = self->max_queued;
        self->n_refused_full++;
      } else {
        if (self->tail) {
          self->tail->next = fw;
        } else {
          self->head = fw;
        }
        self->tail = fw;
        self->queued++;
        self->n_forwarded++;
        pthread_cond_signal(&self->queued_cv);
        fw = NULL;  /* the queue's now */
      }
      pthread_mutex_unlock(&self->mu);
    }
    if (fw != NULL) {
      free_forward(fw);
    }
    if (full) {
      char text[256];
      snprintf(text, sizeof(text),
               "check_wrench: %zd requests already wait for the Python handler "
               "(max_queued_requests); nothing computed, try again later", full);
      resp.status = self->st_limit;
      resp.margin = -1.0;
      resp.consistent = false;
      set_string(&resp.message, text);
      if (rcl_send_response(&self->service, id, &resp) != RCL_RET_OK) {
        rcl_reset_error();
      }
    }
  }
  wrenchcone_msgs__srv__CheckWrench_Response__fini(&resp);
}

static void * serve_loop(void * arg)
{
  Lane * self = arg;
  rcl_allocator_t alloc = rcl_get_default_allocator();
  rcl_wait_set_t ws = rcl_get_zero_initialized_wait_set();
  if (rcl_wait_set_init(&ws, 0, 1, 0, 0, 1, 0, self->node->context, alloc) != RCL_RET_OK) {
    rcl_reset_error();
    return NULL;
  }
  Request req;
  wrenchcone_msgs__srv__CheckWrench_Request__init(&req);
  while (!__atomic_load_n(&self->stopping, __ATOMIC_ACQUIRE)) {
    ignore(rcl_wait_set_clear(&ws));
    ignore(rcl_wait_set_add_service(&ws, &self->service, NULL));
    ignore(rcl_wait_set_add_guard_condition(&ws, &self->stop, NULL));
    rcl_ret_t ret = rcl_wait(&ws, RCL_S_TO_NS(1));
    if (ret == RCL_RET_TIMEOUT) {
      continue;
    }
    if (ret != RCL_RET_OK) {
      rcl_reset_error();
      if (!rcl_context_is_valid(self->node->context)) {
        break;  /* the context is shut down: nothing more to serve */
      }
      struct timespec pause = {0, 1000000};  /* never a busy loop on an error */
      nanosleep(&pause, NULL);
      continue;
    }
    for (;;) {
      rmw_request_id_t id;
      ret = rcl_take_request(&self->service, &id, &req);
      if (ret != RCL_RET_OK) {
        rcl_reset_error();
        break;
      }
      serve_one(self, &id, &req);
    }
  }
  wrenchcone_msgs__srv__CheckWrench_Request__fini(&req);
  ignore(rcl_wait_set_fini(&ws));
  __atomic_store_n(&self->thread_ended, 1, __ATOMIC_RELEASE);
  return NULL;
}

/* --- Python interface ---------------------------------------------------------------- */
static void * pointer_of(PyObject * obj)
{
  return PyLong_AsVoidPtr(obj);
}

static int Lane_init(Lane * self, PyObject * args, PyObject * kwds)
{
  static char * kw[] = {"clock", "cone_tolerance", "smallest", "largest",
                        "ok", "infeasible", "internal_error", "limit_exceeded", NULL};
  PyObject * clock;
  unsigned char ok, infeasible, internal, limit;
  if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odddbbbb", kw, &clock, &self->cone_tol,
                                   &self->smallest, &self->largest, &ok, &infeasible,
                                   &internal, &limit)) {
    return -1;
  }
  self->clock = pointer_of(clock);
  if (self->clock == NULL) {
    if (!PyErr_Occurred()) {
      PyErr_SetString(PyExc_ValueError, "clock must be an rcl_clock_t pointer");
    }
    return -1;
  }
  self->st_ok = ok; self->st_infeasible = infeasible; self->st_internal = internal;
  self->st_limit = limit;
  self->max_queued = 64;  /* set_config sets the node's max_queued_requests */
  pthread_mutex_init(&self->mu, NULL);
  pthread_cond_init(&self->queued_cv, NULL);
  rcl_allocator_t alloc = rcl_get_default_allocator();
  self->pose = rmw_get_zero_initialized_serialized_message();
  self->scratch = rmw_get_zero_initialized_serialized_message();
  if (rmw_serialized_message_init(&self->pose, 256, &alloc) != RMW_RET_OK ||
      rmw_serialized_message_init(&self->scratch, 256, &alloc) != RMW_RET_OK) {
    rcl_reset_error();
    PyErr_NoMemory();
    return -1;
  }
  self->newest_ns = -1;
  self->oldest_ns = self->pose_until_ns = self->fresh_until_ns = -1;
  self->frame_id = dup_str("", 0);
  return 0;
}

static PyObject * Lane_close(Lane * self, PyObject * Py_UNUSED(ignored));

static void Lane_dealloc(Lane * self)
{
  PyObject * r = Lane_close(self, NULL);
  Py_XDECREF(r);
  PyErr_Clear();
  free_entries(self->entries, self->n_entries);
  free(self->frame_id);
  ignore(rmw_serialized_message_fini(&self->pose));
  ignore(rmw_serialized_message_fini(&self->scratch));
  rcl_reset_error();
  pthread_cond_destroy(&self->queued_cv);
  pthread_mutex_destroy(&self->mu);
  Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject * Lane_attach_poses(Lane * self, PyObject * args)
{
  PyObject * sub, * wake;
  if (!PyArg_ParseTuple(args, "OO", &sub, &wake)) {
    return NULL;
  }
  void * s = pointer_of(sub), * w = pointer_of(wake);
  if (PyErr_Occurred()) {
    return NULL;
  }
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  self->sub = s;
  self->wake = w;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  Py_RETURN_NONE;
}

static PyObject * Lane_take_pose(Lane * self, PyObject * Py_UNUSED(ignored))
{
  char * buf = NULL;
  size_t len = 0;
  long long received = 0;
  int have;
  Py_BEGIN_ALLOW_THREADS  /* never wait for the mutex holding the GIL */
  pthread_mutex_lock(&self->mu);
  drain_poses(self);
  have = self->have_pose;
  if (have) {
    len = self->pose.buffer_length;
    buf = malloc(len + 1);
    if (buf != NULL) {
      memcpy(buf, self->pose.buffer, len);
    }
    received = (long long)self->pose_ns;
    self->have_pose = 0;
  }
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  if (!have) {
    Py_RETURN_NONE;
  }
  if (buf == NULL) {
    return PyErr_NoMemory();
  }
  PyObject * out = Py_BuildValue("(y#L)", buf, (Py_ssize_t)len, received);
  free(buf);
  return out;
}

static PyObject * Lane_set_config(Lane * self, PyObject * args)
{
  Py_ssize_t max_queued;
  if (!PyArg_ParseTuple(args, "n", &max_queued)) {
    return NULL;
  }
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  self->max_queued = max_queued < 1 ? 1 : max_queued;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  Py_RETURN_NONE;
}

static PyObject * Lane_clear(Lane * self, PyObject * Py_UNUSED(ignored))
{
  Entry * old;
  Py_ssize_t n;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  self->generation++;
  old = self->entries; n = self->n_entries;
  self->entries = NULL; self->n_entries = 0;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  free_entries(old, n);
  Py_RETURN_NONE;
}

static PyObject * Lane_generation(Lane * self, PyObject * Py_UNUSED(ignored))
{
  uint64_t g;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  g = self->generation;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  return PyLong_FromUnsignedLongLong(g);
}

/* One entry from (mode, status, message, feasible, inv_l, F, E, L, rays, projections):
 * rows of 3; the projections as 3 rows each (a 3x3 matrix, row-major). */
static int parse_entry(Lane * self, PyObject * item, Entry * e)
{
  const char * mode, * message;
  Py_ssize_t n_mode, n_message;
  unsigned char status;
  int feasible;
  PyObject * F, * E, * L, * R, * P;
  if (!PyArg_ParseTuple(item, "s#bs#pdOOOOO", &mode, &n_mode, &status, &message,
                        &n_message, &feasible, &e->inv_l, &F, &E, &L, &R, &P)) {
    return -1;
  }
  if (status != self->st_ok && status != self->st_infeasible) {
    PyErr_SetString(PyExc_ValueError, "an entry's status must be OK or MODE_INFEASIBLE");
    return -1;
  }
  e->status = status;
  e->feasible = feasible;
  e->mode = dup_str(mode, n_mode);
  e->message = dup_str(message, n_message);
  if (e->mode == NULL || e->message == NULL) {
    PyErr_NoMemory();
    return -1;
  }
  Py_ssize_t n_rows = 0;
  if (rows_of(F, "F", &e->F, &e->nF) || rows_of(E, "E", &e->E, &e->nE) ||
      rows_of(L, "L", &e->L, &e->nL) || rows_of(R, "rays", &e->R, &e->nR) ||
      rows_of(P, "projections", &e->P, &n_rows)) {
    return -1;
  }
  if (n_rows % 3 != 0) {
    PyErr_SetString(PyExc_ValueError, "projections must be 3 rows per 3x3 matrix");
    return -1;
  }
  e->nP = n_rows / 3;
  return 0;
}

/* set_entries(generation, snapshot, entries) -> bool: False (nothing changed) when a
 * clear() came after `generation` was read. snapshot = (version, frame_id, pose_stamp,
 * fixels_stamp, oldest_received_ns (-1: none), pose_until_ns, fresh_until_ns), stamps
 * (sec, nanosec). */
static PyObject * Lane_set_entries(Lane * self, PyObject * args)
{
  unsigned long long generation, version;
  const char * frame;
  Py_ssize_t n_frame;
  int pose_sec, fixels_sec;
  unsigned int pose_nsec, fixels_nsec;
  long long oldest_ns, pose_until_ns, fresh_until_ns;
  PyObject * items;
  if (!PyArg_ParseTuple(args, "K(Ks#(iI)(iI)LLL)O", &generation, &version, &frame,
                        &n_frame, &pose_sec, &pose_nsec, &fixels_sec, &fixels_nsec,
                        &oldest_ns, &pose_until_ns, &fresh_until_ns, &items)) {
    return NULL;
  }
  PyObject * seq = PySequence_Fast(items, "entries must be a sequence");
  if (seq == NULL) {
    return NULL;
  }
  Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
  Entry * entries = calloc((size_t)n + 1, sizeof(Entry));
  char * frame_id = dup_str(frame, n_frame);
  if (entries == NULL || frame_id == NULL) {
    free(entries); free(frame_id); Py_DECREF(seq);
    return PyErr_NoMemory();
  }
  for (Py_ssize_t i = 0; i < n; ++i) {
    if (parse_entry(self, PySequence_Fast_GET_ITEM(seq, i), &entries[i]) != 0) {
      free_entries(entries, n); free(frame_id); Py_DECREF(seq);
      return NULL;
    }
  }
  Py_DECREF(seq);
  int applied;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  applied = generation == self->generation;
  if (applied) {
    Entry * old = self->entries;
    Py_ssize_t n_old = self->n_entries;
    char * old_frame = self->frame_id;
    self->entries = entries; self->n_entries = n;
    self->version = version; self->frame_id = frame_id;
    self->pose_sec = pose_sec; self->pose_nsec = pose_nsec;
    self->fixels_sec = fixels_sec; self->fixels_nsec = fixels_nsec;
    self->oldest_ns = oldest_ns;
    self->pose_until_ns = pose_until_ns;
    self->fresh_until_ns = fresh_until_ns;
    entries = old; n = n_old; frame_id = old_frame;
  }
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  free_entries(entries, n);
  free(frame_id);
  return PyBool_FromLong(applied);
}

/* check(mode, fx, fy, tz) -> (consistent, margin) or None: the kernel on its own (tests). */
static PyObject * Lane_check(Lane * self, PyObject * args)
{
  const char * mode;
  Py_ssize_t n;
  double g[3];
  if (!PyArg_ParseTuple(args, "s#ddd", &mode, &n, &g[0], &g[1], &g[2])) {
    return NULL;
  }
  int contains = 0, found, ret = 0;
  double margin = -1.0;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  const Entry * e = find_entry(self, mode, (size_t)n);
  found = e != NULL;
  if (found) {
    ret = check(e, self->cone_tol, g, &contains, &margin);
  }
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  if (!found) {
    Py_RETURN_NONE;
  }
  if (ret != 0) {
    PyErr_SetString(PyExc_ValueError, "wrench must be finite");
    return NULL;
  }
  return Py_BuildValue("(Nd)", PyBool_FromLong(contains), margin);
}

/* usable() -> bool: whether the entries may answer now (the deadlines set_entries gave). */
static PyObject * Lane_usable(Lane * self, PyObject * Py_UNUSED(ignored))
{
  int ok;
  double age;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  ok = usable(self, now_ns(self), &age);
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  return PyBool_FromLong(ok);
}

/* serve(node_pointer, service_name, convert_from_py_capsule): create the service and
 * start its thread; what it cannot answer waits for next_forwarded(). */
static PyObject * Lane_serve(Lane * self, PyObject * args)
{
  PyObject * node, * capsule;
  const char * name;
  if (!PyArg_ParseTuple(args, "OsO", &node, &name, &capsule)) {
    return NULL;
  }
  if (self->serving) {
    PyErr_SetString(PyExc_RuntimeError, "the lane serves already");
    return NULL;
  }
  self->convert = (convert_from_py_t)PyCapsule_GetPointer(capsule, NULL);
  self->node = pointer_of(node);
  if (self->convert == NULL || self->node == NULL) {
    if (!PyErr_Occurred()) {
      PyErr_SetString(PyExc_ValueError, "a null node pointer or converter");
    }
    return NULL;
  }
  self->service = rcl_get_zero_initialized_service();
  rcl_service_options_t options = rcl_service_get_default_options();
  const rosidl_service_type_support_t * ts =
    ROSIDL_GET_SRV_TYPE_SUPPORT(wrenchcone_msgs, srv, CheckWrench);
  if (rcl_service_init(&self->service, self->node, ts, name, &options) != RCL_RET_OK) {
    PyErr_Format(PyExc_RuntimeError, "creating the service %s failed: %s", name,
                 rcl_get_error_string().str);
    rcl_reset_error();
    return NULL;
  }
  self->stop = rcl_get_zero_initialized_guard_condition();
  if (rcl_guard_condition_init(&self->stop, self->node->context,
                               rcl_guard_condition_get_default_options()) != RCL_RET_OK) {
    PyErr_Format(PyExc_RuntimeError, "a guard condition failed: %s",
                 rcl_get_error_string().str);
    rcl_reset_error();
    ignore(rcl_service_fini(&self->service, self->node));
    return NULL;
  }
  self->stopping = 0;
  self->thread_ended = 0;
  self->accepting = 1;
  if (pthread_create(&self->thread, NULL, serve_loop, self) != 0) {
    self->accepting = 0;
    ignore(rcl_guard_condition_fini(&self->stop));
    ignore(rcl_service_fini(&self->service, self->node));
    PyErr_SetString(PyExc_RuntimeError, "starting the check_wrench thread failed");
    return NULL;
  }
  self->serving = 1;
  Py_RETURN_NONE;
}

static void forward_capsule_free(PyObject * capsule)
{
  Forward * fw = PyCapsule_GetPointer(capsule, "wrenchcone_ros.fastcheck.Forward");
  if (fw != NULL) {
    free_forward(fw);
  }
  PyErr_Clear();
}

/* next_forwarded(timeout_s) -> (token, mode, (fx, fy, fz, tx, ty, tz), classify), None
 * after timeout_s without one, or False once the lane is closed. */
static PyObject * Lane_next_forwarded(Lane * self, PyObject * args)
{
  double timeout;
  if (!PyArg_ParseTuple(args, "d", &timeout)) {
    return NULL;
  }
  Forward * fw = NULL;
  int closed = 0;
  Py_BEGIN_ALLOW_THREADS
  struct timespec until;
  clock_gettime(CLOCK_REALTIME, &until);
  double whole = floor(timeout > 0 ? timeout : 0);
  until.tv_sec += (time_t)whole;
  until.tv_nsec += (long)((timeout - whole) * 1e9);
  if (until.tv_nsec >= 1000000000L) {
    until.tv_sec += 1;
    until.tv_nsec -= 1000000000L;
  }
  pthread_mutex_lock(&self->mu);
  while (self->head == NULL && !self->stopping) {
    if (pthread_cond_timedwait(&self->queued_cv, &self->mu, &until) != 0) {
      break;
    }
  }
  closed = self->stopping;
  if (!closed && self->head != NULL) {
    fw = self->head;
    self->head = fw->next;
    if (self->head == NULL) {
      self->tail = NULL;
    }
    fw->next = NULL;
    self->queued--;
  }
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  if (closed) {
    Py_RETURN_FALSE;
  }
  if (fw == NULL) {
    Py_RETURN_NONE;
  }
  PyObject * token = PyCapsule_New(fw, "wrenchcone_ros.fastcheck.Forward",
                                   forward_capsule_free);
  if (token == NULL) {
    free_forward(fw);
    return NULL;
  }
  const geometry_msgs__msg__Vector3 * f = &fw->req.wrench.force, * m = &fw->req.wrench.torque;
  PyObject * mode = PyUnicode_DecodeUTF8(fw->req.mode.data, (Py_ssize_t)fw->req.mode.size,
                                         "replace");
  if (mode == NULL) {
    Py_DECREF(token);
    return NULL;
  }
  return Py_BuildValue("(NN(dddddd)N)", token, mode, f->x, f->y, f->z, m->x, m->y, m->z,
                       PyBool_FromLong(fw->req.classify));
}

/* respond(token, response) -> bool: send the Python handler's CheckWrench.Response;
 * False when the lane is closed, the token was used, or the response did not convert
 * (then INTERNAL_ERROR is sent instead). */
static PyObject * Lane_respond(Lane * self, PyObject * args)
{
  PyObject * token, * response;
  if (!PyArg_ParseTuple(args, "OO", &token, &response)) {
    return NULL;
  }
  Forward * fw = PyCapsule_GetPointer(token, "wrenchcone_ros.fastcheck.Forward");
  if (fw == NULL) {
    return NULL;
  }
  if (fw->responded) {
    Py_RETURN_FALSE;
  }
  fw->responded = 1;
  Response resp;
  if (!wrenchcone_msgs__srv__CheckWrench_Response__init(&resp)) {
    return PyErr_NoMemory();
  }
  int converted = self->convert != NULL && self->convert(response, &resp);
  if (!converted) {
    PyErr_Clear();
    wrenchcone_msgs__srv__CheckWrench_Response__fini(&resp);
    wrenchcone_msgs__srv__CheckWrench_Response__init(&resp);
    resp.status = self->st_internal;
    resp.margin = -1.0;
    set_string(&resp.message, "check_wrench failed: the reply could not be converted");
  }
  int sent = 0;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  if (!converted) {
    self->n_failed++;
  }
  if (self->accepting) {
    sent = rcl_send_response(&self->service, &fw->id, &resp) == RCL_RET_OK;
    rcl_reset_error();
  }
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  wrenchcone_msgs__srv__CheckWrench_Response__fini(&resp);
  return PyBool_FromLong(sent && converted);
}

/* Stop serving (join the thread, destroy the service) and forget every pointer. */
static PyObject * Lane_close(Lane * self, PyObject * Py_UNUSED(ignored))
{
  Forward * queue = NULL;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  self->stopping = 1;
  self->accepting = 0;  /* respond() sends nothing from now on */
  pthread_cond_broadcast(&self->queued_cv);
  queue = self->head;
  self->head = self->tail = NULL;
  self->queued = 0;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  while (queue != NULL) {  /* requests no one will answer: the node is going */
    Forward * next = queue->next;
    free_forward(queue);
    queue = next;
  }
  if (self->serving) {
    ignore(rcl_trigger_guard_condition(&self->stop));
    Py_BEGIN_ALLOW_THREADS
    pthread_join(self->thread, NULL);
    Py_END_ALLOW_THREADS
    ignore(rcl_guard_condition_fini(&self->stop));
    ignore(rcl_service_fini(&self->service, self->node));
    self->serving = 0;
  }
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  self->sub = NULL;
  self->wake = NULL;
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  Py_RETURN_NONE;
}

static PyObject * Lane_stats(Lane * self, PyObject * Py_UNUSED(ignored))
{
  uint64_t fast, fwd, failed, poses, full, by[16];
  Py_ssize_t queued;
  Py_BEGIN_ALLOW_THREADS
  pthread_mutex_lock(&self->mu);
  fast = self->n_fast; fwd = self->n_forwarded; failed = self->n_failed;
  poses = self->n_poses_in_service; full = self->n_refused_full; queued = self->queued;
  memcpy(by, self->n_fast_status, sizeof(by));
  pthread_mutex_unlock(&self->mu);
  Py_END_ALLOW_THREADS
  PyObject * statuses = PyDict_New();
  for (int i = 0; statuses && i < 16; ++i) {
    if (by[i]) {
      PyObject * k = PyLong_FromLong(i), * v = PyLong_FromUnsignedLongLong(by[i]);
      if (k && v) {
        PyDict_SetItem(statuses, k, v);
      }
      Py_XDECREF(k); Py_XDECREF(v);
    }
  }
  int serving = self->serving && !__atomic_load_n(&self->thread_ended, __ATOMIC_ACQUIRE);
  return Py_BuildValue("{sKsKsKsKsNsNsnsK}", "fast", (unsigned long long)fast,
                       "forwarded", (unsigned long long)fwd, "failed",
                       (unsigned long long)failed, "poses_taken", (unsigned long long)poses,
                       "fast_statuses", statuses, "serving", PyBool_FromLong(serving),
                       "queued", queued, "refused_queue_full", (unsigned long long)full);
}

static PyMethodDef Lane_methods[] = {
  {"attach_poses", (PyCFunction)Lane_attach_poses, METH_VARARGS,
   "attach_poses(subscription_pointer, wake_guard_pointer): take poses from this rcl "
   "subscription; trigger this guard condition when the service thread took one."},
  {"take_pose", (PyCFunction)Lane_take_pose, METH_NOARGS,
   "take_pose() -> (serialized bytes, received_ns) of the newest pose, or None."},
  {"set_config", (PyCFunction)Lane_set_config, METH_VARARGS,
   "set_config(max_queued): at most this many requests wait for the Python handler."},
  {"clear", (PyCFunction)Lane_clear, METH_NOARGS,
   "clear(): forget every entry (an input other than the pose changed)."},
  {"generation", (PyCFunction)Lane_generation, METH_NOARGS,
   "generation() -> int, to pass to set_entries."},
  {"set_entries", (PyCFunction)Lane_set_entries, METH_VARARGS,
   "set_entries(generation, snapshot, entries) -> bool"},
  {"check", (PyCFunction)Lane_check, METH_VARARGS,
   "check(mode, fx, fy, tz) -> (consistent, margin), or None without that entry."},
  {"usable", (PyCFunction)Lane_usable, METH_NOARGS,
   "usable() -> bool: whether the entries may answer now (the deadlines Python gave)."},
  {"serve", (PyCFunction)Lane_serve, METH_VARARGS,
   "serve(node_pointer, service_name, convert_from_py_capsule)"},
  {"next_forwarded", (PyCFunction)Lane_next_forwarded, METH_VARARGS,
   "next_forwarded(timeout_s) -> (token, mode, wrench6, classify) | None | False"},
  {"respond", (PyCFunction)Lane_respond, METH_VARARGS,
   "respond(token, CheckWrench.Response) -> bool (sent)"},
  {"close", (PyCFunction)Lane_close, METH_NOARGS, "close(): stop serving."},
  {"stats", (PyCFunction)Lane_stats, METH_NOARGS,
   "stats() -> {'fast', 'forwarded', 'failed', 'poses_taken' (by the service thread), "
   "'fast_statuses', 'serving' (the thread runs), 'queued' (waiting for the Python "
   "handler now), 'refused_queue_full'}"},
  {NULL, NULL, 0, NULL}
};

static PyTypeObject LaneType = {
  PyVarObject_HEAD_INIT(NULL, 0)
  .tp_name = "wrenchcone_ros.node._fastcheck.Lane",
  .tp_doc = "check_wrench answered from the monitored cones without the GIL.",
  .tp_basicsize = sizeof(Lane),
  .tp_flags = Py_TPFLAGS_DEFAULT,
  .tp_new = PyType_GenericNew,
  .tp_init = (initproc)Lane_init,
  .tp_dealloc = (destructor)Lane_dealloc,
  .tp_methods = Lane_methods,
};

static struct PyModuleDef module = {
  PyModuleDef_HEAD_INIT, "_fastcheck",
  "check_wrench answered without the Python interpreter (src/fastcheck.c).", -1, NULL,
  NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit__fastcheck(void)
{
  if (PyType_Ready(&LaneType) < 0) {
    return NULL;
  }
  PyObject * m = PyModule_Create(&module);
  if (m == NULL) {
    return NULL;
  }
  Py_INCREF(&LaneType);
  if (PyModule_AddObject(m, "Lane", (PyObject *)&LaneType) < 0) {
    Py_DECREF(&LaneType);
    Py_DECREF(m);
    return NULL;
  }
  return m;
}
