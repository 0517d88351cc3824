#include "batch.h"
#include "case_process.h"
#include "memory_budget.h"

#include "common/error_text.h"
#include "common/live_line.h"

#include "vessel/core/errors.h"
#include "vessel/io/flat_io.h"
#include "vessel/io/io.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <sys/prctl.h>
#include <unistd.h>
#include <vector>

namespace vessel::cli {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Set by the first SIGINT/SIGTERM; workers stop taking new meshes. The handler resets itself
// (SA_RESETHAND), so a second signal ends the process at once: only `.tmp` files can then be
// left behind, and the next run removes them.
std::atomic<int> g_signal{0};

extern "C" void on_signal(int sig)
{
    g_signal = sig;
    static const char message[] =
        "\nvessel-flatten: interrupted; finishing the running meshes (interrupt again to "
        "abandon them)\n";
    [[maybe_unused]] const auto n = ::write(2, message, sizeof(message) - 1);
}

void install_signal_handlers()
{
    struct sigaction action = {};
    action.sa_handler = on_signal;
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

struct Row
{
    std::string file;
    std::string stem;
    std::string status = "interrupted";
    std::string message = "not processed: the batch was interrupted; rerun with --resume";
    bool resumed = false;
    double total_s = 0;
    long faces = 0;
    int flipped = 0;
    double area_ratio = 0;
    double mean_abs_log_area = 0;
    double peak_mb = 0;  //!< peak resident memory of the mesh's process (0: not run)
};

bool is_mesh_file(const fs::path& p)
{
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl" ||
           ext == ".vtp" || ext == ".vtk";
}

std::string trimmed(const std::string& s)
{
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string::npos)
        return "";
    return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

// An input and the base name of its outputs (<name>.obj, <name>.json); `refused` is set for a
// directory entry that cannot be read at all (a dangling or looping link, an unreadable folder).
struct Input
{
    std::string file;
    std::string name;
    std::string refused;
};

// Every mesh entry of the directory \p spec (recursively) with, for those that cannot be read,
// the reason, and every subfolder that cannot be listed (its meshes unknown) with the reason;
// links are followed to files, never to folders (no cycles).
std::vector<std::pair<std::string, std::string>> directory_entries(const std::string& spec)
{
    std::vector<std::pair<std::string, std::string>> found;
    std::error_code ec;
    fs::recursive_directory_iterator it(spec, ec), end;
    if (ec)
        throw InvalidInputError("--batch: cannot list " + spec + ": " + ec.message() +
                                "; check the folder's permissions");
    for (; it != end; it.increment(ec))
    {
        if (ec)
        {
            // Not an unreadable subfolder (those are probed before the iterator enters them):
            // the listing itself failed, so what is left of it is unknown.
            found.emplace_back(spec, "cannot be listed to the end: " + ec.message());
            break;
        }
        const fs::path path = it->path();
        std::error_code type_ec;
        if (it->is_directory(type_ec) && !it->is_symlink(type_ec))
        {
            std::error_code list_ec;
            const fs::directory_iterator probe(path, list_ec);
            if (list_ec)
            {
                found.emplace_back(path.string(), "is a folder that cannot be listed (" +
                                                      list_ec.message() +
                                                      "); check its permissions");
                it.disable_recursion_pending();
            }
            continue;
        }
        if (!is_mesh_file(path))
            continue;
        std::error_code link_ec;
        const fs::file_status target = fs::status(path, link_ec);
        if (fs::is_symlink(fs::symlink_status(path)) && (link_ec || !fs::exists(target)))
        {
            std::error_code read_ec;
            const fs::path to = fs::read_symlink(path, read_ec);
            found.emplace_back(path.string(),
                               "is a symbolic link to " + to.string() +
                                   (link_ec && link_ec != std::errc::no_such_file_or_directory
                                        ? ", which cannot be resolved (" + link_ec.message() + ")"
                                        : ", which does not exist") +
                                   "; fix or remove the link");
        }
        else if (fs::is_regular_file(target))
            found.emplace_back(path.string(), "");
        else if (!fs::is_directory(target))
            found.emplace_back(path.string(), "is not a regular file; give a mesh file");
    }
    return found;
}

// A directory is searched recursively. Outputs are named by the input's stem, or by its file
// name when several inputs share the stem (x.ply -> x.ply.obj next to x.stl -> x.stl.obj).
std::vector<Input> collect_inputs(const std::string& spec)
{
    std::vector<std::string> files;
    std::map<std::string, std::string> refused;
    if (fs::is_directory(spec))
    {
        for (const auto& [file, reason] : directory_entries(spec))
        {
            files.push_back(file);
            if (!reason.empty())
                refused[file] = file + " " + reason;
        }
        if (files.empty())
            throw InvalidInputError("--batch: no .obj, .off, .ply, .stl, .vtp or .vtk files in " + spec);
    }
    else if (fs::is_regular_file(spec))
    {
        std::ifstream list(spec);
        const fs::path base = fs::path(spec).parent_path();
        std::string line;
        while (std::getline(list, line))
        {
            line = trimmed(line);
            if (line.empty() || line[0] == '#')
                continue;
            const fs::path p(line);
            files.push_back(p.is_absolute() ? p.string() : (base / p).string());
        }
        if (files.empty())
            throw InvalidInputError("--batch: the list " + spec + " names no files");
    }
    else
        throw InvalidInputError("--batch: " + spec + " is neither a directory nor a list file");
    std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
        const auto na = fs::path(a).filename().string(), nb = fs::path(b).filename().string();
        return na != nb ? na < nb : a < b;
    });
    std::map<std::string, int> stems;
    for (const auto& f : files)
        ++stems[fs::path(f).stem().string()];
    std::vector<Input> inputs;
    std::map<std::string, std::string> by_name;
    for (const auto& f : files)
    {
        const fs::path p(f);
        const std::string name =
            stems[p.stem().string()] > 1 ? p.filename().string() : p.stem().string();
        if (name == "summary")
            throw InvalidInputError("--batch: input " + f +
                                    " has the stem 'summary', which would overwrite the batch "
                                    "summary; rename it");
        const auto [it, inserted] = by_name.emplace(name, f);
        if (!inserted)
            throw InvalidInputError("--batch: inputs " + it->second + " and " + f +
                                    " have the same file name, so both would write " + name +
                                    ".obj; rename one of them");
        inputs.push_back({f, name, refused.count(f) ? refused[f] : std::string()});
    }
    return inputs;
}

void remove_quietly(const fs::path& path)
{
    std::error_code ec;
    fs::remove(path, ec);
}

// Leftovers of an abandoned run (a second interrupt ends the process at once) are never valid
// outputs: the temporary files `<name>.obj.XXXXXX.tmp` / `<name>.json.XXXXXX.tmp` of the
// atomic writer (write_text_file()), and `<name>.obj.tmp` of older versions.
void remove_leftovers(const fs::path& dir, const std::vector<Input>& inputs)
{
    std::set<std::string> outputs;
    for (const auto& input : inputs)
        for (const char* ext : {".obj", ".json"})
            outputs.insert(input.name + ext);
    outputs.insert("summary.csv");
    outputs.insert("summary.json");
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec))
    {
        std::string name = entry.path().filename().string();
        if (name.size() < 4 || name.compare(name.size() - 4, 4, ".tmp") != 0)
            continue;
        name.resize(name.size() - 4);  // NAME or NAME.XXXXXX
        const auto dot = name.rfind('.');
        if (outputs.count(name) ||
            (dot != std::string::npos && name.size() - dot == 7 && outputs.count(name.substr(0, dot))))
            remove_quietly(entry.path());
    }
}

// Fills \p row from a mesh's report <name>.json (a success); false if it is unreadable or not
// a success.
bool row_from_report(const fs::path& json_path, Row& row)
{
    try
    {
        std::ifstream in(json_path);
        const nlohmann::json j = nlohmann::json::parse(in);
        if (j.value("status", std::string("ok")) != "ok")
            return false;
        row.status = "ok";
        row.message.clear();
        row.total_s = j.at("timings").at("total").get<double>();
        row.faces = j.at("counts").at("faces").get<long>();
        const auto& q = j.at("quality");
        row.flipped = q.at("flipped_triangles").get<int>();
        row.area_ratio = q.at("area_ratio").get<double>();
        row.mean_abs_log_area = q.at("mean_abs_log_area_ratio").get<double>();
        return true;
    }
    catch (const std::exception&)
    {
        return false;
    }
}

std::string csv_field(const std::string& s)
{
    if (s.find_first_of(",\"\n\r") == std::string::npos)
        return s;
    std::string quoted = "\"";
    for (char c : s)
        quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string number(double x)
{
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.6g", x);
    return buffer;
}

void write_summaries(const fs::path& dir, const std::vector<Row>& rows, int signal)
{
    std::ostringstream csv;
    csv << "file,status,message,resumed,total_s,faces,flipped,area_ratio,"
           "mean_abs_log_area_ratio,peak_mb\n";
    nlohmann::json files = nlohmann::json::array();
    std::map<std::string, int> counts;
    for (const auto& r : rows)
    {
        ++counts[r.status];
        const bool ok = r.status == "ok";
        csv << csv_field(r.file) << "," << r.status << "," << csv_field(r.message) << ","
            << (r.resumed ? "true" : "false") << ",";
        if (ok)
            csv << number(r.total_s) << "," << r.faces << "," << r.flipped << ","
                << number(r.area_ratio) << "," << number(r.mean_abs_log_area);
        else
            csv << ",,,,";
        csv << "," << (r.peak_mb > 0 ? number(r.peak_mb) : "");
        csv << "\n";
        nlohmann::json j = {{"file", r.file},
                            {"status", r.status},
                            {"message", r.message},
                            {"resumed", r.resumed}};
        if (ok)
        {
            j["total_s"] = r.total_s;
            j["faces"] = r.faces;
            j["flipped"] = r.flipped;
            j["area_ratio"] = r.area_ratio;
            j["mean_abs_log_area_ratio"] = r.mean_abs_log_area;
        }
        if (r.peak_mb > 0)
            j["peak_mb"] = r.peak_mb;
        files.push_back(j);
    }
    nlohmann::json summary = {{"inputs", rows.size()},
                              {"ok", counts["ok"]},
                              {"refused", counts["refused"]},
                              {"failed", counts["failed"]},
                              {"interrupted", counts["interrupted"]},
                              {"signal", signal},
                              {"files", files}};
    write_text_file((dir / "summary.csv").string(), csv.str());
    write_text_file((dir / "summary.json").string(), summary.dump(2) + "\n");
}

// 80% of the machine's physical memory, in MB (0 if unknown: then no cap).
double default_memory_mb()
{
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0)
        return 0.0;
    return 0.8 * static_cast<double>(pages) * static_cast<double>(page) / (1024.0 * 1024.0);
}

}  // namespace

std::optional<RepairOptions> BatchOptions::repair_options() const
{
    if (!repair && fill_holes <= 0.0)
        return std::nullopt;
    RepairOptions r;
    if (!repair)  // only the holes
        r.remove_duplicate_faces = r.orient = r.stitch_borders = r.remove_degenerate_faces = false;
    r.fill_holes_below = fill_holes;
    return r;
}

int run_batch(const BatchOptions& batch, const FlattenOptions& options)
{
    std::vector<Input> files;
    try
    {
        files = collect_inputs(batch.inputs);
        fs::create_directories(batch.output_dir);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-flatten: %s\n", e.what());
        return 1;
    }
    const fs::path dir = batch.output_dir;
    remove_leftovers(dir, files);
    std::vector<Row> rows(files.size());
    std::vector<std::size_t> todo;
    for (std::size_t i = 0; i < files.size(); ++i)
    {
        Row& row = rows[i];
        row.file = files[i].file;
        row.stem = files[i].name;
        if (!files[i].refused.empty())
        {
            row.status = "refused";
            row.message = files[i].refused;
            remove_quietly(dir / (row.stem + ".obj"));  // no earlier output may contradict it
            remove_quietly(dir / (row.stem + ".json"));
            continue;
        }
        const fs::path obj = dir / (row.stem + ".obj"), json = dir / (row.stem + ".json");
        if (batch.resume && fs::exists(obj) && fs::exists(json) && row_from_report(json, row))
        {
            row.resumed = true;
            continue;
        }
        todo.push_back(i);
    }

    // OpenMesh's warnings would interleave between the meshes; our messages say what matters.
    omerr().disable();
    const double memory_mb = batch.memory_mb > 0.0 ? batch.memory_mb : default_memory_mb();
    const double cap = memory_mb > 0.0 ? memory_mb : std::numeric_limits<double>::infinity();
    MemoryBudget budget(cap);
    MemoryWatchdog watchdog(cap, std::chrono::milliseconds(50));
    std::mutex print_mutex;
    std::atomic<std::size_t> next{0};
    std::size_t finished = files.size() - todo.size();
    // On a terminal a status line says how many meshes are done, and names the one running
    // longest with its seconds so far (and how many more run beside it): a large mesh's minutes
    // are not silent.
    LiveLine live = LiveLine::on_terminal(batch.quiet);
    // The meshes running, in the order they started, under print_mutex (as `finished`).
    std::vector<std::pair<std::string, Clock::time_point>> running;
    const auto show_running = [&] {  // the caller holds print_mutex
        const std::string done =
            "[" + std::to_string(finished) + "/" + std::to_string(files.size()) + "] ";
        if (running.empty())
            return live.show(done + "done");
        const std::string more =
            running.size() > 1 ? " (+" + std::to_string(running.size() - 1) + " more)" : "";
        live.show(done + "running " + running.front().first + more, running.front().second);
    };
    g_signal = 0;
    install_signal_handlers();
    std::signal(SIGPIPE, SIG_IGN);  // a mesh's process that ended is seen by its exit status

    // Each mesh runs in a process of its own (vessel-flatten ... --batch-case FILE NAME,
    // run_batch_case()), which reads and validates the mesh, says its size, waits for the
    // budget to admit it, flattens it and writes its outputs and its row.
    auto process = [&](Row& row) {
        std::vector<std::string> args = batch.command;
        args.insert(args.end(), {"--batch-case", row.file, row.stem});
        double need = 0.0;
        bool admitted = false, reported = false;
        ChildProcess::Exit exit;
        MemoryWatchdog::Verdict verdict;
        try
        {
            ChildProcess child("/proc/self/exe", args);
            watchdog.watch(child.pid());
            // Unwatched before the child is reaped on every path (its number could be reused),
            // also when this block throws: declared after `child`, destroyed before it.
            struct Unwatch
            {
                MemoryWatchdog& watchdog;
                pid_t pid;
                ~Unwatch() { watchdog.forget(pid); }
            } unwatch{watchdog, child.pid()};
            std::string line;
            while (child.read_line(line))
            {
                if (line.rfind("faces ", 0) == 0)
                {
                    const std::size_t faces = std::stoul(line.substr(6));
                    need = estimated_peak_mb(faces);
                    if (!budget.acquire(need))
                    {
                        char text[300];
                        std::snprintf(text, sizeof text,
                                      "%zu triangles would need about %.0f MB, above the "
                                      "batch's memory cap of %.0f MB; give a larger "
                                      "--batch-memory, or flatten it alone",
                                      faces, need, budget.cap());
                        row.status = "refused";
                        row.message = text;
                        reported = true;
                        child.kill();
                        break;
                    }
                    admitted = true;
                    watchdog.admit(child.pid(), need);
                    child.write_line("go");
                }
                else if (line.rfind("ok", 0) == 0)
                    reported = row_from_report(dir / (row.stem + ".json"), row);
                else if (line.rfind("refused ", 0) == 0 || line.rfind("failed ", 0) == 0)
                {
                    const auto space = line.find(' ');
                    row.status = line.substr(0, space);
                    row.message = line.substr(space + 1);
                    reported = true;
                }
            }
            verdict = watchdog.forget(child.pid());  // before the pid is reaped
            exit = child.wait();
        }
        catch (const std::exception& e)
        {
            row.status = "failed";
            row.message = std::string("cannot run the mesh's process: ") + e.what();
            reported = true;
        }
        if (admitted)
            budget.release(need);
        // The kernel's high-water mark (ru_maxrss) and /proc/PID/statm, which the watchdog
        // read, come from RSS counters synced at different moments and can differ by a few
        // pages: a process stopped above the cap peaked at least at what the watchdog saw.
        row.peak_mb = verdict.killed ? std::max(exit.peak_mb, verdict.resident_mb) : exit.peak_mb;
        if (verdict.killed)
        {
            char text[400];
            if (verdict.beside == 0)
                std::snprintf(text, sizeof text,
                              "stopped at %.0f MB, above the batch's memory cap of %.0f MB "
                              "(estimate for its size: %.0f MB); give a larger --batch-memory, "
                              "or flatten it alone",
                              verdict.resident_mb, cap, need);
            else
                std::snprintf(text, sizeof text,
                              "stopped at %.0f MB (estimate for its size: %.0f MB): with the %d "
                              "other running mesh%s the batch went above its memory cap of "
                              "%.0f MB; flatten it alone, or give a larger --batch-memory",
                              verdict.resident_mb, need, verdict.beside,
                              verdict.beside == 1 ? "" : "es", cap);
            row.status = "failed";
            row.message = text;
        }
        else if (!reported)
        {
            row.status = admitted ? "failed" : "refused";
            row.message = exit.signal != 0
                              ? "its process ended by signal " + std::to_string(exit.signal) +
                                    " (" + strsignal(exit.signal) + ")"
                              : "its process ended (exit code " + std::to_string(exit.code) +
                                    ") without a result";
            row.message += "; please report it with the mesh";
        }
        if (row.status != "ok")
        {
            // No outputs of this or an earlier run may contradict the summary.
            remove_quietly(dir / (row.stem + ".obj"));
            remove_quietly(dir / (row.stem + ".json"));
            if (admitted)  // only an admitted process writes (its temporary files included)
                remove_leftovers(dir, {Input{row.file, row.stem, ""}});
        }
    };

    auto worker = [&]() {
        while (g_signal == 0)
        {
            const std::size_t k = next++;
            if (k >= todo.size())
                return;
            Row& row = rows[todo[k]];
            {
                std::lock_guard<std::mutex> lock(print_mutex);
                running.emplace_back(row.file, Clock::now());
                show_running();
            }
            process(row);
            std::lock_guard<std::mutex> lock(print_mutex);
            running.erase(std::find_if(running.begin(), running.end(),
                                       [&](const auto& r) { return r.first == row.file; }));
            ++finished;
            if (!batch.quiet)
            {
                char figures[128];
                std::snprintf(figures, sizeof figures,
                              "ok, %d flipped, mean |log area| %.4f, %.3f s", row.flipped,
                              row.mean_abs_log_area, row.total_s);
                live.print("[" + std::to_string(finished) + "/" + std::to_string(files.size()) +
                           "] " + row.file + ": " +
                           (row.status == "ok" ? figures : row.status + ": " + row.message));
            }
            show_running();
        }
    };
    const int jobs =
        static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(batch.jobs, todo.size())));
    std::vector<std::thread> threads;
    for (int t = 0; t < jobs; ++t)
        threads.emplace_back(worker);
    for (auto& t : threads)
        t.join();
    live.hide();

    const int signal = g_signal;
    try
    {
        write_summaries(dir, rows, signal);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-flatten: cannot write the summary: %s\n", e.what());
        return 1;
    }
    const auto bad = std::count_if(rows.begin(), rows.end(),
                                   [](const Row& r) { return r.status != "ok"; });
    if (!batch.quiet || bad > 0)
        std::fprintf(stderr, "vessel-flatten: %zu of %zu meshes flattened; summary in %s\n",
                     rows.size() - static_cast<std::size_t>(bad), rows.size(),
                     (dir / "summary.csv").string().c_str());
    if (signal != 0)
        return 128 + signal;
    return bad > 0 ? 1 : 0;
}

int run_batch_case(const BatchOptions& batch, const FlattenOptions& options,
                   const std::string& file, const std::string& name)
{
    // Ends with the batch (a second interrupt ends it at once); if it has ended already, so do we.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() == 1)
        return 1;
    omerr().disable();
    std::FILE* to_batch = ::fdopen(3, "w");
    if (!to_batch)
    {
        std::fprintf(stderr, "vessel-flatten: --batch-case is the batch's own (one mesh of "
                             "--batch in a process); run --batch instead\n");
        return 1;
    }
    const auto say = [&](const std::string& line) {
        std::fprintf(to_batch, "%s\n", line.c_str());
        std::fflush(to_batch);
    };
    const fs::path dir = batch.output_dir;
    const fs::path obj = dir / (name + ".obj"), json = dir / (name + ".json");
    FlattenOptions mesh_options = options;
    mesh_options.on_stage = nullptr;
    std::string status, message;  // of a mesh not flattened
    bool validated = false;
    try
    {
        auto start = Clock::now();
        const PreparedInput in =
            prepare_input(read_raw_mesh(file), batch.surface, batch.repair_options());
        const TreeSurface& surface = in.surface;
        const double read_s = seconds_since(start);
        // The batch admits the mesh by its size (MemoryBudget), or stops this process.
        say("faces " + std::to_string(surface.mesh.n_faces()));
        std::string answer;
        for (int c; (c = std::getchar()) != EOF && c != '\n';)
            answer.push_back(static_cast<char>(c));
        if (answer != "go")
            return 1;
        validated = true;
        const FlattenResult result = flatten(surface.mesh, mesh_options);
        start = Clock::now();
        write_flat_obj(obj.string(), in.raw.points, result.mesh, result.uv);
        const double write_s = seconds_since(start);
        nlohmann::json report = report_json(file, in, result, read_s, write_s);
        report["status"] = "ok";
        write_text_file(json.string(), report.dump(2) + "\n");
        say("ok");  // the batch's row comes from the report
        return 0;
    }
    catch (const InvalidInputError& e)
    {
        status = validated ? "failed" : "refused";
        message = e.what();
    }
    catch (const IoError& e)
    {
        status = validated ? "failed" : "refused";
        message = e.what();
    }
    catch (const std::exception& e)
    {
        status = "failed";
        message = error_text(e, file);
    }
    catch (...)
    {
        status = "failed";
        message = "unknown exception";
    }
    std::replace(message.begin(), message.end(), '\n', ' ');  // one line to the batch
    say(status + " " + message);
    return 0;
}

}  // namespace vessel::cli
