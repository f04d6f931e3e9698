#include "sweep_runner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "cli_common.hpp"
#include "report.hpp"

namespace mlce::cli {
namespace {

double parse_number(const std::string& text, const std::string& spec) {
  if (const auto v = parse_finite(text)) return *v;
  throw std::invalid_argument("--param " + spec + ": '" + text + "' is not a number");
}

/// Appends lines to the journal, each flushed to disk before the point counts as finished.
class Journal {
 public:
  Journal(const std::string& path, bool fresh, const std::string& signature) : path_(path) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | (fresh ? O_TRUNC : O_APPEND), 0644);
    if (fd_ < 0) throw std::runtime_error(path + ": cannot write the sweep journal");
    if (fresh) write("# mlce sweep journal " + signature + "\n");
  }
  ~Journal() {
    if (fd_ >= 0) ::close(fd_);
  }
  void write(const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex_);
    const char* p = line.data();
    std::size_t left = line.size();
    while (left > 0) {
      const ssize_t n = ::write(fd_, p, left);
      if (n <= 0) throw std::runtime_error(path_ + ": cannot write the sweep journal");
      p += n, left -= static_cast<std::size_t>(n);
    }
    ::fsync(fd_);
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::mutex mutex_;
};

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

/// CSV cells never contain commas or newlines (error notes are sanitised).
std::string clean_cell(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

}  // namespace

std::vector<double> SweepAxis::values() const {
  std::vector<double> v;
  const auto n = static_cast<std::size_t>(std::floor((last - first) / step + 1e-9)) + 1;
  for (std::size_t i = 0; i < n; ++i) v.push_back(first + static_cast<double>(i) * step);
  return v;
}

SweepAxis parse_sweep_axis(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("--param " + spec + ": expected NAME=first:last:step (e.g. rpm=150:350:2)");
  SweepAxis a;
  a.name = spec.substr(0, eq);
  std::vector<std::string> parts;
  std::stringstream in(spec.substr(eq + 1));
  for (std::string p; std::getline(in, p, ':');) parts.push_back(p);
  if (parts.size() == 1) {
    a.first = a.last = parse_number(parts[0], spec);
    return a;
  }
  if (parts.size() != 3) throw std::invalid_argument("--param " + spec + ": expected NAME=first:last:step");
  a.first = parse_number(parts[0], spec);
  a.last = parse_number(parts[1], spec);
  a.step = parse_number(parts[2], spec);
  if (!(a.step > 0)) throw std::invalid_argument("--param " + spec + ": the step must be positive");
  if (a.last < a.first) throw std::invalid_argument("--param " + spec + ": expected first <= last");
  if ((a.last - a.first) / a.step > 1e6) throw std::invalid_argument("--param " + spec + ": more than 10^6 values");
  return a;
}

SweepOutcome run_sweep(const SweepPlan& plan,
                       const std::function<std::vector<std::string>(const std::vector<double>&)>& compute) {
  // Grid, last axis fastest.
  std::vector<std::vector<double>> axis_values;
  std::size_t total = 1;
  for (const auto& a : plan.axes) axis_values.push_back(a.values()), total *= axis_values.back().size();
  if (total > 1000000) throw std::invalid_argument("--param: the grid has more than 10^6 points");
  SweepOutcome out;
  out.points = total;
  out.values.resize(total);
  out.results.resize(total);
  for (std::size_t k = 0; k < total; ++k) {
    std::size_t rest = k;
    std::vector<double> v(plan.axes.size());
    for (std::size_t d = plan.axes.size(); d-- > 0;) {
      v[d] = axis_values[d][rest % axis_values[d].size()];
      rest /= axis_values[d].size();
    }
    out.values[k] = v;
  }
  const std::size_t n_cells = plan.result_columns.size();
  const bool notes = !plan.result_columns.empty() && plan.result_columns.back() == "note";

  // Resume: a journal with the same signature gives the points already finished. A last line
  // cut short by a kill has no newline or the wrong cell count and is ignored.
  const std::string journal_path = plan.out_path + ".partial";
  std::vector<bool> done(total, false);
  bool fresh = true;
  if (std::ifstream in{journal_path}) {
    std::string first;
    std::getline(in, first);
    if (first != "# mlce sweep journal " + plan.signature)
      throw std::runtime_error(journal_path + ": an interrupted sweep with other settings; rerun it with the same "
                               "options or delete the file to start afresh");
    fresh = false;
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t pos = 0;
    while (true) {
      const auto nl = content.find('\n', pos);
      if (nl == std::string::npos) break;
      const auto cells = split_csv(content.substr(pos, nl - pos));
      pos = nl + 1;
      if (cells.size() != 1 + n_cells) continue;
      std::size_t k = 0;
      try {
        k = std::stoul(cells[0]);
      } catch (const std::exception&) {
        continue;
      }
      if (k >= total || done[k]) continue;
      out.results[k].assign(cells.begin() + 1, cells.end());
      done[k] = true;
      ++out.resumed;
    }
    if (pos != content.size() && !plan.quiet)
      std::fprintf(stderr, "mlce: %s: ignored a point cut short by the interruption\n", journal_path.c_str());
  }
  // Rewrite the journal without a torn tail before appending to it.
  if (!fresh) {
    std::string clean = "# mlce sweep journal " + plan.signature + "\n";
    for (std::size_t k = 0; k < total; ++k)
      if (done[k]) {
        clean += std::to_string(k);
        for (const auto& c : out.results[k]) clean += "," + c;
        clean += "\n";
      }
    write_file_atomically(journal_path, clean);
  }
  Journal journal(journal_path, fresh, plan.signature);
  if (!plan.quiet && out.resumed > 0)
    std::fprintf(stderr, "mlce: resuming %s: %zu of %zu points already done\n", plan.out_path.c_str(), out.resumed, total);

  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < total; ++k)
    if (!done[k]) pending.push_back(k);
  const bool chunk = plan.max_new_points > 0 && plan.max_new_points < pending.size();
  if (chunk) pending.resize(plan.max_new_points);
  std::atomic<std::size_t> next{0}, finished{0};
  std::atomic<bool> failed{false};
  std::string failure;
  std::mutex failure_mutex, progress_mutex;
  const auto start = std::chrono::steady_clock::now();
  double last_report = 0;
  auto report = [&](bool final) {
    if (plan.quiet) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!final && (s < 1.0 || s - last_report < 0.5)) return;
    last_report = s;
    const std::size_t f = finished.load();
    const double rate = s > 0 ? static_cast<double>(f) / s : 0.0;
    const double left = rate > 0 ? static_cast<double>(pending.size() - f) / rate : 0.0;
    std::fprintf(stderr, "mlce: sweep %zu/%zu points, %.2f points/s, %.0f s left\n", out.resumed + f, total, rate, left);
  };
  auto worker = [&] {
    while (!failed) {
      const std::size_t t = next++;
      if (t >= pending.size()) return;
      const std::size_t k = pending[t];
      std::vector<std::string> cells;
      try {
        cells = compute(out.values[k]);
        if (cells.size() != n_cells) throw std::logic_error("sweep point returned the wrong number of cells");
      } catch (const std::exception& e) {
        if (!notes) {
          std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failed.exchange(true)) failure = e.what();
          return;
        }
        cells.assign(n_cells, "");  // no value: the note says why
        cells.back() = "error: " + std::string(e.what());
      }
      for (auto& c : cells) c = clean_cell(c);
      std::string line = std::to_string(k);
      for (const auto& c : cells) line += "," + c;
      journal.write(line + "\n");
      out.results[k] = std::move(cells);
      ++finished;
      report(false);
    }
  };
  const unsigned jobs = std::max(1u, std::min<unsigned>(plan.jobs, static_cast<unsigned>(std::max<std::size_t>(pending.size(), 1))));
  std::vector<std::thread> pool;
  for (unsigned j = 1; j < jobs; ++j) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (failed) throw std::runtime_error(failure + " (finished points are kept in " + journal_path + "; rerun to resume)");
  out.computed = finished;
  if (notes)  // points that threw (compute's note "error: ..."); unfinished points have no cells
    out.failed = static_cast<std::size_t>(std::count_if(out.results.begin(), out.results.end(), [](const auto& cells) {
      return !cells.empty() && cells.back().rfind("error: ", 0) == 0;
    }));
  report(true);
  if (chunk) return out;  // the journal keeps them; a rerun continues
  std::error_code ec;
  if (notes && total > 0 && out.failed == total) {
    out.complete = out.all_failed = true;
    std::filesystem::remove(journal_path, ec);
    return out;
  }

  std::string csv = plan.header_comment;
  for (std::size_t d = 0; d < plan.axes.size(); ++d) csv += (d ? "," : "") + plan.axes[d].name;
  for (const auto& c : plan.result_columns) csv += "," + c;
  csv += "\n";
  for (std::size_t k = 0; k < total; ++k) {
    for (std::size_t d = 0; d < plan.axes.size(); ++d) csv += (d ? "," : "") + fmt::format("{:.17g}", out.values[k][d]);
    for (const auto& c : out.results[k]) csv += "," + c;
    csv += "\n";
  }
  write_file_atomically(plan.out_path, csv);
  out.complete = true;
  std::filesystem::remove(journal_path, ec);
  return out;
}

}  // namespace mlce::cli
