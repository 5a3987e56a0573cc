#include "app/core/input_boundary.h"

#include <system_error>

#include "analysis/common/number_text.h"
#include "analysis/common/summary.h"
#include "app/core/campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;

// `p` lies strictly inside `root` (both absolute and normal, compared by their components).
bool lies_inside(const fs::path& root, const fs::path& p) {
  const fs::path rel = p.lexically_relative(root);
  return !rel.empty() && rel != "." && *rel.begin() != "..";
}

fs::path absolute_normal(const fs::path& p) {
  std::error_code ec;
  const fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}

// The root with its own symlinks resolved (a campaign below a symlinked folder).
fs::path canonical_root(const fs::path& root) {
  const fs::path a = absolute_normal(root);
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(a, ec);
  return ec ? a : c.lexically_normal();
}

bool is_loop(const std::error_code& ec) { return ec == std::errc::too_many_symbolic_link_levels; }

}  // namespace

std::string regular_file_problem(const fs::path& file) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (st.type() == fs::file_type::not_found) return "file not found";
  if (ec) {
    if (is_loop(ec)) return "is a symlink loop, not a regular file";
    return "cannot be read (" + ec.message() + ")";
  }
  switch (st.type()) {
    case fs::file_type::regular: {
      const std::uintmax_t bytes = fs::file_size(file, ec);
      if (ec) return "cannot be read (" + ec.message() + ")";
      if (bytes > kMaxInputFileBytes) {
        return "is " + significant_text(static_cast<double>(bytes) / 1e9, 3) +
               " GB, above the 4 GiB limit of an input file";
      }
      return "";
    }
    case fs::file_type::directory:
      return "is a folder, not a regular file";
    case fs::file_type::fifo:
      return "is a FIFO, not a regular file";
    case fs::file_type::socket:
      return "is a socket, not a regular file";
    case fs::file_type::block:
    case fs::file_type::character:
      return "is a device, not a regular file";
    default:
      return "is not a regular file";
  }
}

InputFileCheck check_input_file(const fs::path& campaign_root_in, const fs::path& test_folder,
                                const std::string& value) {
  // A test not loaded from a campaign (no root known): its own folder is the boundary.
  const fs::path& campaign_root = campaign_root_in.empty() ? test_folder : campaign_root_in;
  InputFileCheck c;
  const std::string quoted = "'" + value + "': ";
  if (value.empty()) {
    c.problem = quoted + "names no file";
    return c;
  }
  if (value.find('\0') != std::string::npos) {
    c.problem = quoted + "contains a NUL character";
    return c;
  }
  const fs::path v(value);
  if (v.is_absolute() || v.has_root_name() || v.has_root_directory()) {
    c.problem = quoted +
                "is an absolute path: must be relative to the test folder and lie inside the "
                "campaign folder";
    return c;
  }
  // Lexically first: `..` may climb while the path stays inside the campaign.
  const fs::path root = absolute_normal(campaign_root);
  const fs::path lexical = (absolute_normal(test_folder) / v).lexically_normal();
  if (!lies_inside(root, lexical)) {
    c.problem = quoted + "must lie inside the campaign folder";
    return c;
  }
  // Then with every symlink resolved (in the file's name or any folder above it).
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(lexical, ec);
  if (ec) {
    c.problem = quoted + (is_loop(ec) ? std::string("is a symlink loop, not a regular file")
                                      : "cannot be resolved (" + ec.message() + ")");
    return c;
  }
  if (!lies_inside(canonical_root(campaign_root), target.lexically_normal())) {
    c.problem = quoted + "must lie inside the campaign folder (a symlink leads outside)";
    return c;
  }
  // The file's status, before anything opens it (a FIFO would block an open).
  if (const std::string why = regular_file_problem(target); !why.empty()) {
    c.problem = quoted + why;
    return c;
  }
  c.path = lexical;
  return c;
}

std::string input_file_message(const std::string& yaml_label, const std::string& key,
                               const std::string& problem) {
  return yaml_label + ": key '" + key + "' " + problem;
}

fs::path resolve_input_file(const fs::path& campaign_root, const fs::path& test_folder,
                            const std::string& yaml_label, const std::string& key,
                            const std::string& value) {
  InputFileCheck c = check_input_file(campaign_root, test_folder, value);
  if (!c.ok()) throw InputError(input_file_message(yaml_label, key, c.problem));
  return c.path;
}

fs::path resolve_input_file(const TestSpec& t, const std::string& key, const std::string& value) {
  return resolve_input_file(t.campaign_root, t.folder, t.yaml_label, key, value);
}

bool regular_file_inside(const fs::path& campaign_root, const fs::path& file) {
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(absolute_normal(file), ec);
  if (ec) return false;
  return lies_inside(canonical_root(campaign_root), target.lexically_normal()) &&
         regular_file_problem(target).empty();
}

}  // namespace chatterlab::app
