// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bullet-bench: the time of one world step of Bullet 3.24's
// deformable world on the crumpling ribbon (ribbon_scene.hpp), with selfcol
// as the self-collision (libselfcol_bullet), with Bullet's own, and with
// none, at several sizes (docs/benchmarks.md, "Bullet adapter: time per
// world step").
//
// One run = one size, one mode: build the world and the ribbon, drive the
// ribbon's ends together over W steps (--steps; the drive ends at the last
// step, so the strip folds on itself well before it) and time every
// stepSimulation call. Step 0 is reported alone ("first step": it includes
// every build, selfcol's hierarchy or Bullet's face tree); the last M steps
// (--measure) are the measured window: their median and mean. After the last
// step the cloth's EF interferences (edges crossing triangles) are counted by
// the core library's exact query, independently of the mode. A selfcol run
// whose contacts pass --max-contacts per face has collapsed into a tangle
// and is stopped (row status "diverged"). Each run is a child process of its
// own, so a run's peak memory and heap are its own and a crash is reported,
// not fatal. Runs are interleaved: for each size, each
// repetition runs every mode in turn; the row of a size and mode gives the
// median over its repetitions of each run's figure (median of medians).
#include "ribbon_scene.hpp"

#include <selfcol/selfcol.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

struct size_spec {
    std::string label; // as given: "20k" or "288"
    int along = 0;
    int steps = 0;   // W: the drive's duration and the run's length
    int measure = 0; // M: the measured window, the last M steps
};

// The default run length: the drive's speed in edge lengths per step is the
// same at every size (W = 3.75 x along: 360 steps at 2k faces, 1080 at 20k,
// 3384 at 200k; 1.5, 4.5 and 14 s). With a faster drive the adapter lets
// the cloth cross itself and collapse (20k faces: W = 720 does, 1080 does
// not); at 200k faces it still diverges at step 1557 of 3384
// (docs/benchmarks.md, "Bullet adapter: time per world step").
const double kStepsPerNode = 3.75;

struct config {
    std::vector<size_spec> sizes;
    std::vector<demo::mode> modes{demo::mode::off, demo::mode::bullet, demo::mode::selfcol};
    int steps = 0;   // W for every size; 0: kStepsPerNode x along
    int measure = 0; // M for every size; 0: W / 3
    int repeat = 1;
    double scale = 1;
    double time_limit = 0; // seconds per run, 0: none
    // A run stops when selfcol holds more than this many contacts per face
    // (the cloth has collapsed into a tangle: see "diverged" below).
    double max_contacts = 10;
    double memory_gb = 8; // address-space limit of each run's process
    unsigned threads = 1;
    std::string csv;
    std::string out;   // final frames, "" none
    std::string trace; // per-step CSV of every run, "" none
};

// What one run hands back to the parent through a pipe (plain data).
struct run_result {
    int ok;           // the child finished and reported
    int adapter_ok;   // the adapter's status stayed SELFCOL_OK (selfcol mode)
    int finite;       // every node finite at the end
    int steps_done;   // steps run (W unless the time limit stopped it)
    int diverged;     // stopped: selfcol's contacts passed --max-contacts per face
    int window_first; // the measured window: steps [window_first, window_last]
    int window_last;
    double setup_ms;                           // world, ribbon and adapter set-up, before step 0
    double first_ms;                           // step 0
    double median_ms, mean_ms, min_ms, max_ms; // over the window
    double first_detect_ms;                    // selfcol: its part of step 0
    double detect_median_ms, response_median_ms, detect_mean_ms, response_mean_ms;
    double contacts_mean;  // selfcol VF+EE contacts held, mean over the window
    uint64_t contacts_end; // selfcol: VF+EE held after the last step
    uint64_t interferences_end, crossed_end;
    double bullet_contacts_mean; // Bullet's m_faceNodeContacts, mean over the window
    uint64_t bullet_contacts_end;
    long long ef_end;       // exact EF interferences of the last frame (core query), -1: failed
    double ef_query_ms;     // that query (mesh, hierarchy, query)
    double store_median_ms; // selfcol: the contact store's update, median over the window
    // selfcol: the last frame again, by the core alone at the adapter's
    // distance (all kinds, EXACT, one thread): refit and query, median of 3
    double final_refit_ms, final_query_ms;
    uint64_t final_contacts; // that query's records (VF + EE + EF)
    double ke_end;
    long max_rss_kb;
    double wall_s;
};

const char *mode_name(demo::mode m) {
    return m == demo::mode::selfcol              ? "selfcol"
           : m == demo::mode::selfcol_fresh      ? "selfcol-fresh"
           : m == demo::mode::selfcol_continuous ? "selfcol-continuous"
           : m == demo::mode::bullet             ? "bullet"
                                                 : "off";
}

long long faces_of(int along) {
    int a = along < 16 ? 16 : along;
    int across = a / 8 < 3 ? 3 : a / 8;
    return 2LL * (a - 1) * (across - 1);
}

// "288": along = 288; "20k": the along whose face count is nearest 20,000.
bool parse_size(const std::string &s, size_spec &out) {
    char *end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || !(v > 0))
        return false;
    out.label = s;
    if (*end == '\0') {
        out.along = int(v);
        return out.along >= 16 && double(out.along) == v;
    }
    if ((*end != 'k' && *end != 'K') || end[1] != '\0')
        return false;
    double target = v * 1000;
    long long best = -1;
    for (int a = 16; a <= 16384; ++a) {
        long long d = std::llabs(faces_of(a) - (long long)target);
        if (best < 0 || d < best) {
            best = d;
            out.along = a;
        }
    }
    return true;
}

std::vector<std::string> split(const std::string &s) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (start <= s.size()) {
        size_t comma = s.find(',', start);
        if (comma == std::string::npos)
            comma = s.size();
        if (comma > start)
            parts.push_back(s.substr(start, comma - start));
        start = comma + 1;
    }
    return parts;
}

double median(std::vector<double> v) {
    if (v.empty())
        return NAN;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double> &v) {
    if (v.empty())
        return NAN;
    double s = 0;
    for (double x : v)
        s += x;
    return s / double(v.size());
}

// The exact EF interferences of the cloth as it is now, counted by the core
// library: its own mesh and hierarchy, EXACT, d = 0.1 x mean edge. With
// `distance` > 0 (selfcol mode: the adapter's thickness), it also times a
// refit and an all-kinds query of that frame at that distance, as the
// adapter's scene runs them (median of 3).
void final_frame(const btSoftBody *body, double distance, run_result &r) {
    auto t0 = clock_type::now();
    std::vector<double> x(size_t(body->m_nodes.size()) * 3);
    for (int i = 0; i < body->m_nodes.size(); ++i)
        for (int k = 0; k < 3; ++k)
            x[size_t(i) * 3 + size_t(k)] = double(body->m_nodes[i].m_x[k]);
    std::vector<uint32_t> t(size_t(body->m_faces.size()) * 3);
    const btSoftBody::Node *n0 = &body->m_nodes[0];
    for (int i = 0; i < body->m_faces.size(); ++i)
        for (int k = 0; k < 3; ++k)
            t[size_t(i) * 3 + size_t(k)] = uint32_t(body->m_faces[i].m_n[k] - n0);
    selfcol_mesh *mesh = nullptr;
    selfcol_hierarchy *tree = nullptr;
    selfcol_contacts *contacts = nullptr;
    r.ef_end = -1;
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXACT;
    if (selfcol_mesh_create(&mesh, size_t(body->m_nodes.size()), x.data(),
                            size_t(body->m_faces.size()), t.data(), nullptr) == SELFCOL_OK &&
        selfcol_hierarchy_create(&tree, mesh, nullptr) == SELFCOL_OK &&
        selfcol_contacts_create(&contacts, nullptr) == SELFCOL_OK) {
        q.kinds = SELFCOL_KIND_EF;
        q.distance = 0.1 * selfcol_mesh_mean_edge_length(mesh);
        if (selfcol_hierarchy_self_collide(tree, contacts, &q) == SELFCOL_OK)
            r.ef_end = (long long)selfcol_contacts_count(contacts);
    }
    r.ef_query_ms = 1e3 * seconds_since(t0);
    if (r.ef_end >= 0 && distance > 0) {
        std::vector<double> refit, query;
        q.kinds = SELFCOL_KIND_ALL;
        q.distance = distance;
        for (int k = 0; k < 3; ++k) {
            auto a = clock_type::now();
            selfcol_mesh_set_positions(mesh, x.data(), size_t(body->m_nodes.size()));
            selfcol_hierarchy_refit(tree);
            auto b = clock_type::now();
            if (selfcol_hierarchy_self_collide(tree, contacts, &q) != SELFCOL_OK)
                break;
            refit.push_back(1e3 * std::chrono::duration<double>(b - a).count());
            query.push_back(1e3 * seconds_since(b));
            r.final_contacts = selfcol_contacts_count(contacts);
        }
        r.final_refit_ms = median(refit);
        r.final_query_ms = median(query);
    }
    selfcol_contacts_destroy(contacts);
    selfcol_hierarchy_destroy(tree);
    selfcol_mesh_destroy(mesh);
}

// One run, in the child process.
// The self store's update time of the one cloth (surface 0), part of the
// adapter's seconds_detect; 0 before the scene exists.
double store_seconds(selfcol_bullet *adapter) {
    const selfcol_store *st = nullptr;
    selfcol_store_update_stats us;
    us.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    if (selfcol_scene_store(selfcol_bullet_scene(adapter), 0, 0, &st) == SELFCOL_OK &&
        st != nullptr && selfcol_store_stats(st, &us) == SELFCOL_OK)
        return us.seconds;
    return 0;
}

// One --trace row: step i's times (step, detect, response, store, in ms),
// the adapter's counters and its continuous option's (0 without it).
void trace_step(FILE *trace, const config &cfg, const size_spec &size, demo::mode m, int rep, int i,
                const double times_ms[4], const selfcol_bullet_step_stats &s, size_t bullet_now) {
    std::fprintf(trace,
                 "%s,%s,%g,%d,%d,%.4f,%.4f,%.4f,%.4f,%llu,%llu,%llu,%llu,%llu,%llu,%.4g,%zu,"
                 "%.4f,%llu,%llu,%llu,%llu,%llu,%llu\n",
                 size.label.c_str(), mode_name(m), cfg.scale, rep + 1, i, times_ms[0], times_ms[1],
                 times_ms[2], times_ms[3], (unsigned long long)s.contacts,
                 (unsigned long long)s.interferences, (unsigned long long)s.crossed,
                 (unsigned long long)s.flipped, (unsigned long long)s.corrected,
                 (unsigned long long)s.responses, s.max_push, bullet_now,
                 1e3 * s.seconds_continuous, (unsigned long long)s.continuous_passes,
                 (unsigned long long)s.zone_nodes, (unsigned long long)s.continuous_remaining,
                 (unsigned long long)s.passed_around, (unsigned long long)s.continuous_exempt,
                 (unsigned long long)s.crossings_after);
}

// The window's figures (steps a..b) from the per-step series (seconds, and
// contact counts).
void summarize_window(run_result &r, int a, int b, const std::vector<double> &step_s,
                      const std::vector<double> &detect_s, const std::vector<double> &response_s,
                      const std::vector<double> &store_s, const std::vector<double> &contacts,
                      const std::vector<double> &bcontacts) {
    std::vector<double> ws, wd, wr, wc, wb, wst;
    for (int i = a; i <= b; ++i) {
        ws.push_back(1e3 * step_s[size_t(i)]);
        wd.push_back(1e3 * detect_s[size_t(i)]);
        wr.push_back(1e3 * response_s[size_t(i)]);
        wc.push_back(contacts[size_t(i)]);
        wb.push_back(bcontacts[size_t(i)]);
        wst.push_back(1e3 * store_s[size_t(i)]);
    }
    r.median_ms = median(ws);
    r.mean_ms = mean(ws);
    r.min_ms = ws.empty() ? NAN : *std::min_element(ws.begin(), ws.end());
    r.max_ms = ws.empty() ? NAN : *std::max_element(ws.begin(), ws.end());
    r.detect_median_ms = median(wd);
    r.response_median_ms = median(wr);
    r.detect_mean_ms = mean(wd);
    r.response_mean_ms = mean(wr);
    r.store_median_ms = median(wst);
    r.contacts_mean = mean(wc);
    r.bullet_contacts_mean = mean(wb);
}

run_result run_one(const config &cfg, const size_spec &size, demo::mode m, int rep) {
    run_result r;
    std::memset(&r, 0, sizeof r);
    auto started = clock_type::now();
    demo::options o;
    o.collision = m;
    o.scale = cfg.scale;
    o.threads = cfg.threads;
    o.quiet = true;
    demo::world w(o, 0.0);
    demo::ribbon rib = demo::add_ribbon(w, size.along, cfg.scale, size.steps);
    if (w.start(o) != 0)
        return r;
    r.setup_ms = 1e3 * seconds_since(started);

    const int steps = size.steps;
    const int window_first = std::max(1, steps - size.measure);
    std::vector<double> step_s, detect_s, response_s, store_s, contacts, bcontacts;
    // Sized before the loop: no allocation between the timed steps.
    for (std::vector<double> *v :
         {&step_s, &detect_s, &response_s, &store_s, &contacts, &bcontacts})
        v->reserve(size_t(steps));
    selfcol_bullet_step_stats s;
    std::memset(&s, 0, sizeof s);
    s.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    r.adapter_ok = 1;
    int report_every = std::max(1, steps / 6);
    FILE *trace = cfg.trace.empty() ? nullptr : std::fopen(cfg.trace.c_str(), "a");
    int done = 0;
    for (int i = 0; i < steps; ++i) {
        demo::drive_ribbon(rib, i);
        auto t0 = clock_type::now();
        w.step(demo::step_length());
        double dt = seconds_since(t0);
        step_s.push_back(dt);
        done = i + 1;
        double det = 0, resp = 0, store = 0;
        if (w.adapter != nullptr) {
            selfcol_bullet_stats(w.adapter, &s);
            if (s.status != SELFCOL_OK)
                r.adapter_ok = 0;
            det = s.seconds_detect;
            resp = s.seconds_response;
            store = store_seconds(w.adapter);
        }
        store_s.push_back(store);
        const size_t bullet_now = demo::bullet_contacts(w);
        if (trace != nullptr) {
            const double times_ms[4] = {1e3 * dt, 1e3 * det, 1e3 * resp, 1e3 * store};
            trace_step(trace, cfg, size, m, rep, i, times_ms, s, bullet_now);
        }
        detect_s.push_back(det);
        response_s.push_back(resp);
        contacts.push_back(w.adapter != nullptr ? double(s.contacts) : 0.0);
        bcontacts.push_back(double(bullet_now));
        if (i == 0) {
            r.first_ms = 1e3 * dt;
            r.first_detect_ms = 1e3 * det;
        }
        if ((i + 1) % report_every == 0 || i == 0)
            std::fprintf(stderr, "  [%s %s r%d] step %d/%d: %.1f ms%s%s\n", size.label.c_str(),
                         mode_name(m), rep + 1, i, steps, 1e3 * dt,
                         w.adapter != nullptr ? ", selfcol contacts " : "",
                         w.adapter != nullptr ? std::to_string(s.contacts).c_str() : "");
        if (w.adapter != nullptr &&
            double(s.contacts) > cfg.max_contacts * double(rib.body->m_faces.size()) &&
            i + 1 < steps) {
            std::fprintf(stderr,
                         "  [%s %s r%d] diverged: %llu contacts (more than %g per face) after %d "
                         "steps; stopped\n",
                         size.label.c_str(), mode_name(m), rep + 1, (unsigned long long)s.contacts,
                         cfg.max_contacts, done);
            r.diverged = 1;
            break;
        }
        if (cfg.time_limit > 0 && seconds_since(started) > cfg.time_limit && i + 1 < steps) {
            std::fprintf(stderr, "  [%s %s r%d] time limit (%.0f s) after %d steps\n",
                         size.label.c_str(), mode_name(m), rep + 1, cfg.time_limit, done);
            break;
        }
    }
    r.steps_done = done;
    if (trace != nullptr)
        std::fclose(trace);
    // The window: the last M steps, or, when the time limit stopped the run
    // before it, every step after the first (flagged partial by the caller).
    int a = done > window_first ? window_first : 1, b = done - 1;
    r.window_first = a;
    r.window_last = b;
    summarize_window(r, a, b, step_s, detect_s, response_s, store_s, contacts, bcontacts);
    if (w.adapter != nullptr) {
        r.contacts_end = s.contacts;
        r.interferences_end = s.interferences;
        r.crossed_end = s.crossed;
    }
    r.bullet_contacts_end = demo::bullet_contacts(w);
    r.ke_end = demo::kinetic_energy(w);
    r.finite = demo::finite(w) ? 1 : 0;
    final_frame(rib.body, w.adapter != nullptr ? s.distance : 0.0, r);
    if (!cfg.out.empty()) {
        std::string path = cfg.out + "/ribbon-" + size.label + "-" + mode_name(m) + "-r" +
                           std::to_string(rep + 1) + ".ply";
        if (!demo::write_ply(w, path))
            std::fprintf(stderr, "cannot write %s\n", path.c_str());
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    r.max_rss_kb = ru.ru_maxrss;
    r.wall_s = seconds_since(started);
    r.ok = 1;
    return r;
}

// Runs one run in a child process and reads its result back.
run_result run_child(const config &cfg, const size_spec &size, demo::mode m, int rep) {
    run_result r;
    std::memset(&r, 0, sizeof r);
    int fd[2];
    std::fflush(stdout);
    std::fflush(stderr);
    if (pipe(fd) != 0) {
        std::perror("pipe");
        return r;
    }
    pid_t pid = fork();
    if (pid < 0) {
        std::perror("fork");
        close(fd[0]);
        close(fd[1]);
        return r;
    }
    if (pid == 0) {
        close(fd[0]);
        if (cfg.memory_gb > 0) {
            // A run that runs away fails alone instead of pushing the machine into swap.
            struct rlimit lim;
            lim.rlim_cur = lim.rlim_max = rlim_t(cfg.memory_gb * 1073741824.0);
            setrlimit(RLIMIT_AS, &lim);
        }
        run_result mine = run_one(cfg, size, m, rep);
        const char *p = reinterpret_cast<const char *>(&mine);
        size_t left = sizeof mine;
        while (left > 0) {
            ssize_t n = write(fd[1], p, left);
            if (n <= 0)
                _exit(3);
            p += n;
            left -= size_t(n);
        }
        close(fd[1]);
        std::fflush(stderr);
        _exit(0);
    }
    close(fd[1]);
    char *p = reinterpret_cast<char *>(&r);
    size_t got = 0;
    while (got < sizeof r) {
        ssize_t n = read(fd[0], p + got, sizeof r - got);
        if (n <= 0)
            break;
        got += size_t(n);
    }
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (got != sizeof r || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "  [%s %s r%d] the run failed (%s)\n", size.label.c_str(),
                     mode_name(m), rep + 1,
                     WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "no result");
        std::memset(&r, 0, sizeof r);
    }
    return r;
}

// The row of one size and mode: medians over its runs.
struct row {
    size_spec size;
    demo::mode m;
    std::vector<run_result> runs; // the successful ones
    int attempted = 0;
};

template <class F> double med_of(const row &w, F f) {
    std::vector<double> v;
    for (const run_result &r : w.runs)
        v.push_back(double(f(r)));
    return median(v);
}

std::string status_of(const row &w) {
    if (w.runs.empty())
        return "failed";
    bool partial = false, adapter = true, finite = true, diverged = false;
    for (const run_result &r : w.runs) {
        diverged = diverged || r.diverged;
        partial = partial || (r.steps_done < w.size.steps && !r.diverged);
        adapter = adapter && r.adapter_ok;
        finite = finite && r.finite;
    }
    std::string s = diverged ? "diverged" : partial ? "partial" : "ok";
    if (!adapter)
        s += "+adapter-error";
    if (!finite)
        s += "+nonfinite";
    return s;
}

std::string fmt(double v, const char *f = "%.3f") {
    if (std::isnan(v))
        return "";
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

int usage(const char *name) {
    std::fprintf(
        stderr,
        "usage: %s [--sizes LIST] [--modes LIST] [--steps W] [--measure M] "
        "[--repeat N]\n"
        "          [--csv FILE] [--scale S] [--time-limit SECONDS] [--threads N] "
        "[--out DIR]\n"
        "          [--max-contacts F] [--memory-limit GB] [--trace FILE]\n"
        "  --sizes LIST    comma-separated ribbon sizes: Nk = the resolution nearest N "
        "thousand faces,\n"
        "                  a plain N = N nodes along the strip (default 2k,20k)\n"
        "  --modes LIST    of off, bullet, selfcol, selfcol-fresh (a fresh query every\n"
        "                  step: adapter option coherent = 0), selfcol-continuous (the\n"
        "                  continuous option); default off,bullet,selfcol\n"
        "  --steps W       steps per run; the ends are driven together over all of "
        "them\n"
        "                  (default auto: 3.75 x the nodes along, rounded to 12)\n"
        "  --measure M     the measured window: the last M steps (default auto: W / "
        "3)\n"
        "  --repeat N      runs per size and mode, interleaved (default 1)\n"
        "  --csv FILE      write the rows as CSV (also printed)\n"
        "  --scale S       every length times S (default 1)\n"
        "  --time-limit S  stop a run after S seconds (its row is then 'partial')\n"
        "  --max-contacts F  stop a selfcol run (row 'diverged') when its contacts "
        "pass F per face (default 10)\n"
        "  --memory-limit GB  address-space limit of each run (default 8, 0: none)\n"
        "  --threads N     selfcol threads (refits, queries, stores; default 1)\n"
        "  --out DIR       write each run's last frame as DIR/ribbon-SIZE-MODE-rK.ply\n"
        "  --trace FILE    one CSV row per step of every run (times, selfcol's counters)\n",
        name);
    return 2;
}

// Parses the options into cfg and the sizes; returns -1 to go on, else the
// exit status (usage printed).
int parse_options(int argc, char **argv, config &cfg) {
    std::string sizes = "2k,20k";
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--help" || a == "-h")
            return usage(argv[0]);
        if (i + 1 >= argc) {
            std::fprintf(stderr, "%s: %s needs a value\n", argv[0], a.c_str());
            return usage(argv[0]);
        }
        std::string v = argv[++i];
        char *end = nullptr;
        bool bad = false;
        if (a == "--sizes")
            sizes = v;
        else if (a == "--modes") {
            cfg.modes.clear();
            for (const std::string &m : split(v)) {
                if (m == "off")
                    cfg.modes.push_back(demo::mode::off);
                else if (m == "bullet")
                    cfg.modes.push_back(demo::mode::bullet);
                else if (m == "selfcol")
                    cfg.modes.push_back(demo::mode::selfcol);
                else if (m == "selfcol-fresh")
                    cfg.modes.push_back(demo::mode::selfcol_fresh);
                else if (m == "selfcol-continuous")
                    cfg.modes.push_back(demo::mode::selfcol_continuous);
                else
                    bad = true;
            }
            bad = bad || cfg.modes.empty();
        } else if (a == "--steps") {
            cfg.steps = v == "auto" ? 0 : int(std::strtol(v.c_str(), &end, 10));
            bad = cfg.steps < 2 && !(cfg.steps == 0 && v == "auto");
        } else if (a == "--measure") {
            cfg.measure = v == "auto" ? 0 : int(std::strtol(v.c_str(), &end, 10));
            bad = cfg.measure < 1 && !(cfg.measure == 0 && v == "auto");
        } else if (a == "--repeat") {
            cfg.repeat = int(std::strtol(v.c_str(), &end, 10));
            bad = cfg.repeat < 1;
        } else if (a == "--scale") {
            cfg.scale = std::strtod(v.c_str(), &end);
            bad = !(cfg.scale > 0);
        } else if (a == "--time-limit") {
            cfg.time_limit = std::strtod(v.c_str(), &end);
            bad = !(cfg.time_limit >= 0);
        } else if (a == "--max-contacts") {
            cfg.max_contacts = std::strtod(v.c_str(), &end);
            bad = !(cfg.max_contacts > 0);
        } else if (a == "--memory-limit") {
            cfg.memory_gb = std::strtod(v.c_str(), &end);
            bad = !(cfg.memory_gb >= 0);
        } else if (a == "--threads") {
            cfg.threads = unsigned(std::strtoul(v.c_str(), &end, 10));
            bad = cfg.threads < 1;
        } else if (a == "--csv")
            cfg.csv = v;
        else if (a == "--out")
            cfg.out = v;
        else if (a == "--trace")
            cfg.trace = v;
        else {
            std::fprintf(stderr, "%s: unknown option %s\n", argv[0], a.c_str());
            return usage(argv[0]);
        }
        if (bad || (end != nullptr && (*end != '\0' || end == v.c_str()))) {
            std::fprintf(stderr, "%s: bad value for %s: %s\n", argv[0], a.c_str(), v.c_str());
            return usage(argv[0]);
        }
    }
    for (const std::string &s : split(sizes)) {
        size_spec z;
        if (!parse_size(s, z)) {
            std::fprintf(stderr, "%s: bad size %s (Nk or a resolution of at least 16)\n", argv[0],
                         s.c_str());
            return usage(argv[0]);
        }
        z.steps = cfg.steps > 0 ? cfg.steps : int(std::lround(kStepsPerNode * z.along / 12)) * 12;
        z.measure = std::max(1, std::min(cfg.measure > 0 ? cfg.measure : z.steps / 3, z.steps - 1));
        cfg.sizes.push_back(z);
    }
    if (cfg.sizes.empty())
        return usage(argv[0]);

    if (cfg.sizes.empty())
        return usage(argv[0]);
    return -1;
}

// What the runs will be, on stdout; the --trace file started with its
// header. Returns 0 or 1 (the trace file cannot be written).
int print_plan(const config &cfg) {
    std::printf("selfcol-bullet-bench: crumpling ribbon, steps of %.6f s, %d repetition(s), "
                "scale %g, selfcol threads %u\n",
                demo::step_length(), cfg.repeat, cfg.scale, cfg.threads);
    for (const size_spec &z : cfg.sizes)
        std::printf("  size %s: along %d, %lld faces, %d steps (the drive lasts all of them), "
                    "window = the last %d\n",
                    z.label.c_str(), z.along, faces_of(z.along), z.steps, z.measure);
    if (!cfg.trace.empty()) {
        FILE *f = std::fopen(cfg.trace.c_str(), "w");
        if (f == nullptr) {
            std::fprintf(stderr, "cannot write %s\n", cfg.trace.c_str());
            return 1;
        }
        std::fprintf(f, "size,mode,scale,run,step,step_ms,detect_ms,response_ms,store_ms,contacts,"
                        "interferences,crossed,flipped,corrected,responses,max_push,"
                        "bullet_contacts,continuous_ms,continuous_passes,zone_nodes,"
                        "continuous_remaining,passed_around,continuous_exempt,crossings_after\n");
        std::fclose(f);
    }
    return 0;
}

// Every run, interleaved: for each size, each repetition runs every mode in
// turn (a child process each); one line per run on stdout.
std::vector<row> run_all(const config &cfg) {
    std::vector<row> rows;
    for (const size_spec &z : cfg.sizes) {
        size_t first_row = rows.size();
        for (demo::mode m : cfg.modes) {
            row w;
            w.size = z;
            w.m = m;
            rows.push_back(w);
        }
        for (int rep = 0; rep < cfg.repeat; ++rep)
            for (size_t k = 0; k < cfg.modes.size(); ++k) {
                row &w = rows[first_row + k];
                ++w.attempted;
                run_result r = run_child(cfg, z, w.m, rep);
                if (!r.ok)
                    continue;
                w.runs.push_back(r);
                std::printf(
                    "run %s (along %d, %lld faces) %-7s r%d: first %.1f ms, window "
                    "[%d, %d] median %.2f ms mean %.2f ms (selfcol %.2f + %.2f ms, store %.2f; "
                    "last frame by the core: refit %.2f + query %.2f ms), "
                    "contacts %llu, bullet contacts %llu, EF at end %lld, %.1f s\n",
                    z.label.c_str(), z.along, faces_of(z.along), mode_name(w.m), rep + 1,
                    r.first_ms, r.window_first, r.window_last, r.median_ms, r.mean_ms,
                    r.detect_median_ms, r.response_median_ms, r.store_median_ms, r.final_refit_ms,
                    r.final_query_ms, (unsigned long long)r.contacts_end,
                    (unsigned long long)r.bullet_contacts_end, r.ef_end, r.wall_s);
                std::fflush(stdout);
            }
    }
    return rows;
}

// The median step without self-collision of w's size (NAN: none ran).
double off_median_of(const std::vector<row> &rows, const row &w) {
    double off_median = NAN;
    for (const row &o : rows)
        if (o.size.label == w.size.label && o.m == demo::mode::off && !o.runs.empty())
            off_median = med_of(o, [](const run_result &r) { return r.median_ms; });
    return off_median;
}

const char *const csv_header =
    "size,along,across,nodes,faces,mode,scale,threads,steps,measured,repeats,runs_ok,status,"
    "steps_done,setup_ms,first_step_ms,step_median_ms,step_mean_ms,step_min_ms,step_max_ms,"
    "ratio_to_off,first_detect_ms,detect_median_ms,response_median_ms,detect_mean_ms,"
    "response_mean_ms,store_median_ms,final_refit_ms,final_query_ms,final_contacts,"
    "contacts_mean,contacts_end,interferences_end,crossed_end,"
    "bullet_contacts_mean,bullet_contacts_end,ef_end_min,ef_end_max,ef_query_ms,ke_end,"
    "max_rss_kb,wall_s";

// The CSV line of one row: medians over its runs.
std::string csv_line(const config &cfg, const std::vector<row> &rows, const row &w) {
    int across = std::max(3, std::max(16, w.size.along) / 8);
    int along = std::max(16, w.size.along);
    double off_median = off_median_of(rows, w);
    double median_ms = med_of(w, [](const run_result &r) { return r.median_ms; });
    long long ef_min = -1, ef_max = -1, done = w.size.steps;
    double wall = 0;
    for (const run_result &r : w.runs) {
        ef_min = ef_min < 0 ? r.ef_end : std::min(ef_min, r.ef_end);
        ef_max = std::max(ef_max, r.ef_end);
        done = std::min(done, (long long)r.steps_done);
        wall += r.wall_s;
    }
    double step_min = NAN, step_max = NAN;
    for (const run_result &r : w.runs) {
        step_min = std::isnan(step_min) ? r.min_ms : std::min(step_min, r.min_ms);
        step_max = std::isnan(step_max) ? r.max_ms : std::max(step_max, r.max_ms);
    }
    bool sc = w.m == demo::mode::selfcol || w.m == demo::mode::selfcol_fresh ||
              w.m == demo::mode::selfcol_continuous;
    char b[2048];
    std::snprintf(
        b, sizeof b,
        "%s,%d,%d,%d,%lld,%s,%g,%u,%d,%d,%d,%zu,%s,%lld,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,"
        "%s,%s,%s,%s,%s,%s,%s,%s,%s,%lld,%lld,%s,%s,%s,%s",
        w.size.label.c_str(), along, across, along * across, faces_of(w.size.along), mode_name(w.m),
        cfg.scale, cfg.threads, w.size.steps, w.size.measure, cfg.repeat, w.runs.size(),
        status_of(w).c_str(), w.runs.empty() ? 0LL : done,
        fmt(med_of(w, [](const run_result &r) { return r.setup_ms; })).c_str(),
        fmt(med_of(w, [](const run_result &r) { return r.first_ms; })).c_str(),
        fmt(median_ms).c_str(),
        fmt(med_of(w, [](const run_result &r) { return r.mean_ms; })).c_str(),
        fmt(step_min).c_str(), fmt(step_max).c_str(), fmt(median_ms / off_median, "%.2f").c_str(),
        sc ? fmt(med_of(w, [](const run_result &r) { return r.first_detect_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.detect_median_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.response_median_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.detect_mean_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.response_mean_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.store_median_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.final_refit_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.final_query_ms; })).c_str() : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.final_contacts; }), "%.0f").c_str()
           : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.contacts_mean; }), "%.0f").c_str()
           : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.contacts_end; }), "%.0f").c_str()
           : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.interferences_end; }), "%.0f").c_str()
           : "",
        sc ? fmt(med_of(w, [](const run_result &r) { return r.crossed_end; }), "%.0f").c_str() : "",
        w.m == demo::mode::bullet
            ? fmt(med_of(w, [](const run_result &r) { return r.bullet_contacts_mean; }), "%.0f")
                  .c_str()
            : "",
        w.m == demo::mode::bullet
            ? fmt(med_of(w, [](const run_result &r) { return r.bullet_contacts_end; }), "%.0f")
                  .c_str()
            : "",
        ef_min, ef_max, fmt(med_of(w, [](const run_result &r) { return r.ef_query_ms; })).c_str(),
        fmt(med_of(w, [](const run_result &r) { return r.ke_end; }), "%.4g").c_str(),
        fmt(med_of(w, [](const run_result &r) { return double(r.max_rss_kb); }), "%.0f").c_str(),
        fmt(wall, "%.1f").c_str());
    return b;
}

// The rows as CSV: on stdout and into --csv. Returns 0 or 1 (--csv cannot be
// written).
int write_rows(const config &cfg, const std::vector<row> &rows) {
    std::vector<std::string> lines;
    for (const row &w : rows)
        lines.push_back(csv_line(cfg, rows, w));
    std::printf("\n%s\n", csv_header);
    for (const std::string &l : lines)
        std::printf("%s\n", l.c_str());
    if (!cfg.csv.empty()) {
        FILE *f = std::fopen(cfg.csv.c_str(), "w");
        if (f == nullptr) {
            std::fprintf(stderr, "cannot write %s\n", cfg.csv.c_str());
            return 1;
        }
        std::fprintf(f, "%s\n", csv_header);
        for (const std::string &l : lines)
            std::fprintf(f, "%s\n", l.c_str());
        if (std::fclose(f) != 0) {
            std::fprintf(stderr, "cannot write %s\n", cfg.csv.c_str());
            return 1;
        }
    }
    return 0;
}

// The rows as a table on stdout.
void print_table(const std::vector<row> &rows) {
    std::printf("\n%-6s %8s %-8s %5s %10s %10s %9s %7s %18s %9s %9s %8s\n", "size", "faces", "mode",
                "runs", "first ms", "median ms", "mean ms", "x off", "selfcol det+resp", "contacts",
                "EF end", "status");
    for (const row &w : rows) {
        double off_median = off_median_of(rows, w);
        double median_ms = med_of(w, [](const run_result &r) { return r.median_ms; });
        long long ef_min = -1, ef_max = -1;
        for (const run_result &r : w.runs) {
            ef_min = ef_min < 0 ? r.ef_end : std::min(ef_min, r.ef_end);
            ef_max = std::max(ef_max, r.ef_end);
        }
        std::string ef = ef_min == ef_max ? std::to_string(ef_min)
                                          : std::to_string(ef_min) + "-" + std::to_string(ef_max);
        std::string split_ms, contacts;
        if (w.m == demo::mode::selfcol || w.m == demo::mode::selfcol_fresh ||
            w.m == demo::mode::selfcol_continuous) {
            split_ms =
                fmt(med_of(w, [](const run_result &r) { return r.detect_median_ms; }), "%.2f") +
                " + " +
                fmt(med_of(w, [](const run_result &r) { return r.response_median_ms; }), "%.2f");
            contacts = fmt(med_of(w, [](const run_result &r) { return r.contacts_end; }), "%.0f");
        } else if (w.m == demo::mode::bullet)
            contacts =
                fmt(med_of(w, [](const run_result &r) { return r.bullet_contacts_end; }), "%.0f");
        std::printf("%-6s %8lld %-8s %2zu/%-2d %10s %10s %9s %7s %18s %9s %9s %8s\n",
                    w.size.label.c_str(), faces_of(w.size.along), mode_name(w.m), w.runs.size(),
                    w.attempted,
                    fmt(med_of(w, [](const run_result &r) { return r.first_ms; }), "%.1f").c_str(),
                    fmt(median_ms, "%.2f").c_str(),
                    fmt(med_of(w, [](const run_result &r) { return r.mean_ms; }), "%.2f").c_str(),
                    fmt(median_ms / off_median, "%.2f").c_str(), split_ms.c_str(), contacts.c_str(),
                    ef.c_str(), status_of(w).c_str());
    }
    std::printf("(contacts: selfcol's VF+EE held after the last step, or Bullet's vertex-face "
                "contacts; EF end: the last frame's exact EF interferences, core query)\n");
}

} // namespace

int main(int argc, char **argv) {
    config cfg;
    int status = parse_options(argc, argv, cfg);
    if (status >= 0)
        return status;
    if (print_plan(cfg) != 0)
        return 1;
    auto all_started = clock_type::now();
    std::vector<row> rows = run_all(cfg);
    // The rows: CSV (stdout and --csv) and a table.
    if (write_rows(cfg, rows) != 0)
        return 1;
    print_table(rows);
    std::printf("total %.1f s\n", seconds_since(all_started));
    for (const row &w : rows)
        if (w.runs.size() != size_t(w.attempted))
            return 1;
    return 0;
}
