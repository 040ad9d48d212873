#include "experiments/tables.h"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

#include <glog/logging.h>

#include "core/atomic_file.h"

namespace msdeform {
namespace {

std::string RunCommand(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[256];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  return output;
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

std::string SanitiseCell(std::string cell) {
  for (char& c : cell)
    if (c == ',' || c == '\n' || c == '|') c = ';';
  return cell;
}

}  // namespace

void Table::AddRow(std::vector<std::string> row) {
  CHECK_EQ(row.size(), columns.size()) << title;
  rows.push_back(std::move(row));
}

std::string FormatNumber(double value, int significant) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

std::string FormatFixed(double value, int decimals) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::vector<std::string> ProvenanceLines(const std::string& source_dir) {
  std::string commit = RunCommand("git -C '" + source_dir + "' rev-parse --short HEAD 2>/dev/null");
  if (commit.empty()) {
    commit = "unknown";
  } else if (!RunCommand("git -C '" + source_dir + "' status --porcelain --untracked-files=no "
                         "2>/dev/null").empty()) {
    commit += "+uncommitted";
  }
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return {"machine: nproc " + std::to_string(std::thread::hardware_concurrency()) + ", " +
              CpuModel(),
          "commit: " + commit, std::string("date: ") + date};
}

bool WriteTable(const std::string& out_dir, const std::string& stem, const Table& table,
                const std::vector<std::string>& header, std::string* error) {
  std::ostringstream csv, md;
  for (const std::string& line : header) csv << "# " << line << "\n";
  for (size_t c = 0; c < table.columns.size(); ++c)
    csv << (c ? "," : "") << SanitiseCell(table.columns[c]);
  csv << "\n";
  for (const auto& row : table.rows) {
    for (size_t c = 0; c < row.size(); ++c) csv << (c ? "," : "") << SanitiseCell(row[c]);
    csv << "\n";
  }
  md << "# " << table.title << "\n\n";
  for (const std::string& line : header) md << "- " << line << "\n";
  md << "\n|";
  for (const std::string& column : table.columns) md << " " << SanitiseCell(column) << " |";
  md << "\n|";
  for (size_t c = 0; c < table.columns.size(); ++c) md << "---|";
  md << "\n";
  for (const auto& row : table.rows) {
    md << "|";
    for (const std::string& cell : row) md << " " << SanitiseCell(cell) << " |";
    md << "\n";
  }
  if (!table.notes.empty()) {
    md << "\n";
    for (const std::string& note : table.notes) md << note << "\n";
  }
  for (const auto& [extension, text] :
       {std::make_pair(std::string(".csv"), csv.str()), std::make_pair(std::string(".md"), md.str())}) {
    const std::string& content = text;
    if (!WriteFileAtomically(
            out_dir + "/" + stem + extension,
            [&](std::ostream& out, std::string*) {
              out << content;
              return static_cast<bool>(out);
            },
            error)) {
      return false;
    }
  }
  return true;
}

bool ReadTableCsv(const std::string& path, std::vector<std::string>* columns,
                  std::vector<std::vector<std::string>>* rows, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return false;
  }
  columns->clear();
  rows->clear();
  std::string line;
  bool have_columns = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    if (!have_columns) {
      *columns = cells;
      have_columns = true;
    } else {
      if (cells.size() != columns->size()) {
        *error = path + ": a row has " + std::to_string(cells.size()) + " cells, expected " +
                 std::to_string(columns->size());
        return false;
      }
      rows->push_back(cells);
    }
  }
  if (!have_columns) {
    *error = path + ": no column names";
    return false;
  }
  return true;
}

}  // namespace msdeform
