// Writes the seed corpus of the fuzz targets into OUTDIR: a coarse folded
// sheet with one hole, with texture coordinates from its flat layout, in every
// format and encoding (OBJ, PLY binary and ASCII, OFF, STL binary and ASCII);
// then variants of it in the shapes hostile files take, for the fuzzers to
// mutate from: byte order marks and other encodings, CR-only line ends, signed
// zeros and special values in STL corners, counts that lie, and PLY vertex
// elements with a coordinate repeated or missing.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "foldfill/examples.h"
#include "foldfill/file.h"
#include "foldfill/io.h"

namespace {

foldfill::Mesh holed_sheet() {
  foldfill::FoldedSheetOptions options;
  options.width = 1;
  options.height = 1;
  options.edge_length = 0.2;
  options.amplitude = 0.1;
  options.folds = 1;
  const foldfill::CutMesh cut =
      foldfill::cut_disk_hole(foldfill::make_folded_sheet(options), {0.5, 0.5}, 0.25);
  foldfill::Mesh mesh = cut.cut.mesh;
  mesh.texcoords = cut.cut.flat;
  mesh.face_texcoords = mesh.faces;
  return mesh;
}

// `text` with its `n`-th (from 0) occurrence of `from` replaced by `to`;
// unchanged when there are fewer.
std::string replace_nth(std::string text, const std::string& from, const std::string& to,
                        int n = 0) {
  size_t at = text.find(from);
  for (int i = 0; i < n && at != std::string::npos; ++i) at = text.find(from, at + 1);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// `text` with every other occurrence of `from`, from the second on, replaced by `to`.
std::string replace_every_other(std::string text, const std::string& from, const std::string& to) {
  bool odd = false;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + 1)) {
    if (odd) {
      text.replace(at, from.size(), to);
      at += to.size() - from.size();  // the next search starts where it would have
    }
    odd = !odd;
  }
  return text;
}

std::string utf16_little_endian(const std::string& text) {
  std::string out = "\xFF\xFE";
  for (char c : text) {
    out += c;
    out += '\0';
  }
  return out;
}

std::string cr_only(std::string text) {
  for (char& c : text) {
    if (c == '\n') c = '\r';
  }
  return text;
}

// The line of `text` that starts at `start` (without its line end).
std::string line_at(const std::string& text, size_t start) {
  return text.substr(start, text.find('\n', start) - start);
}

// The line `line` with its last number changed by `delta`.
std::string with_count_changed(const std::string& line, long long delta) {
  const size_t last = line.find_last_of(' ') + 1;
  return line.substr(0, last) + std::to_string(std::stoll(line.substr(last)) + delta);
}

constexpr size_t kStlHeader = 80;
constexpr size_t kStlFacet = 50;

// The binary STL `stl` with the header `header` (padded to 80 bytes).
std::string with_stl_header(const std::string& stl, std::string header) {
  header.resize(kStlHeader, ' ');
  return header + stl.substr(kStlHeader);
}

// The binary STL `stl` with corner coordinate `k` (0..8) of facet `facet` set
// to the float of bit pattern `bits`.
void set_stl_corner_bits(std::string& stl, size_t facet, size_t k, uint32_t bits) {
  const size_t at = kStlHeader + 4 + facet * kStlFacet + 12 + 4 * k;
  if (at + 4 <= stl.size()) std::memcpy(&stl[at], &bits, 4);  // little endian hosts
}

void write(const std::string& dir, const std::string& name, const std::string& bytes) {
  foldfill::write_file_atomically(dir + "/" + name, bytes);
}

void write_variants(const std::string& dir, const foldfill::Mesh& mesh) {
  using foldfill::MeshFormat;
  const std::string obj = foldfill::serialize_mesh(mesh, MeshFormat::Obj);
  const std::string off = foldfill::serialize_mesh(mesh, MeshFormat::Off);
  const std::string ascii_ply = foldfill::serialize_mesh(mesh, MeshFormat::Ply, {false});
  const std::string binary_ply = foldfill::serialize_mesh(mesh, MeshFormat::Ply, {true});
  const std::string ascii_stl = foldfill::serialize_mesh(mesh, MeshFormat::Stl, {false});
  const std::string binary_stl = foldfill::serialize_mesh(mesh, MeshFormat::Stl, {true});
  const std::string bom = "\xEF\xBB\xBF";

  // Encodings: a UTF-8 byte order mark (valid), UTF-16, CR-only line ends.
  const std::pair<const char*, const std::string*> texts[] = {
      {".obj", &obj}, {".off", &off}, {"_ascii.ply", &ascii_ply}, {"_ascii.stl", &ascii_stl}};
  for (const auto& [suffix, text] : texts) {
    write(dir, std::string("bom_utf8") + suffix, bom + *text);
    write(dir, std::string("bom_utf16") + suffix, utf16_little_endian(*text));
    write(dir, std::string("cr_only") + suffix, cr_only(*text));
  }
  write(dir, "bom_utf8_binary.ply", bom + binary_ply);
  write(dir, "bom_header_binary.stl", with_stl_header(binary_stl, bom + "solid binary"));

  // STL corners: -0 beside +0 (valid), then NaNs of either sign, infinities and
  // denormals.
  std::string signed_zeros = binary_stl;
  const size_t facets = mesh.faces.size();
  for (size_t f = 1; f < facets; f += 2) {
    for (size_t k = 0; k < 9; ++k) {
      const size_t at = kStlHeader + 4 + f * kStlFacet + 12 + 4 * k;
      uint32_t bits;
      std::memcpy(&bits, &signed_zeros[at], 4);
      if (bits == 0) set_stl_corner_bits(signed_zeros, f, k, 0x80000000u);
    }
  }
  write(dir, "signed_zeros_binary.stl", signed_zeros);
  write(dir, "signed_zeros_ascii.stl", replace_every_other(ascii_stl, " 0 ", " -0 "));
  std::string specials = signed_zeros;
  const uint32_t kSpecials[] = {0x7fc00000u, 0xffc00000u, 0x7f800001u, 0x7f800000u,
                                0xff800000u, 0x00000001u, 0x807fffffu, 0x00800000u};
  for (size_t i = 0; i < 8; ++i) set_stl_corner_bits(specials, i, i, kSpecials[i]);
  write(dir, "specials_binary.stl", specials);
  std::string special_text = ascii_stl;
  const char* kSpecialWords[] = {"nan", "-nan", "inf", "-inf", "1e-45", "-0.0", "1e39", "1.2e-38"};
  for (int i = 0; i < 8; ++i) {
    special_text =
        replace_nth(special_text, "vertex 0 ", std::string("vertex ") + kSpecialWords[i] + " ", i);
  }
  write(dir, "specials_ascii.stl", special_text);

  // Counts that lie: one too many or too few, a fraction, a binary STL count.
  const std::string vertices = line_at(ascii_ply, ascii_ply.find("element vertex "));
  const std::string faces = line_at(ascii_ply, ascii_ply.find("element face "));
  const std::string off_counts = line_at(off, off.find('\n') + 1);  // "V F 0"
  const std::string off_faces = off_counts.substr(0, off_counts.find_last_of(' '));
  for (int delta : {-1, 1}) {
    const std::string name = delta < 0 ? "low" : "high";
    write(dir, "count_" + name + "_vertices_ascii.ply",
          replace_nth(ascii_ply, vertices, with_count_changed(vertices, delta)));
    write(dir, "count_" + name + "_faces_ascii.ply",
          replace_nth(ascii_ply, faces, with_count_changed(faces, delta)));
    write(dir, "count_" + name + "_faces_binary.ply",
          replace_nth(binary_ply, faces, with_count_changed(faces, delta)));
    write(dir, "count_" + name + "_faces.off",
          replace_nth(off, off_faces, with_count_changed(off_faces, delta)));
    std::string stl = binary_stl;
    const auto count = static_cast<uint32_t>(facets + delta);
    std::memcpy(&stl[kStlHeader], &count, 4);
    write(dir, "count_" + name + "_binary.stl", stl);
  }
  write(dir, "count_fraction_vertices_ascii.ply",
        replace_nth(ascii_ply, vertices, vertices + ".5"));
  write(dir, "count_fraction_vertices.off",
        replace_nth(off, off_counts, replace_nth(off_counts, " ", ".5 ")));
  write(dir, "truncated_solid_header_binary.stl",
        with_stl_header(binary_stl, "solid binary").substr(0, binary_stl.size() - 7));

  // PLY vertex coordinates repeated or missing.
  const std::pair<const char*, const std::string*> plys[] = {{"_ascii.ply", &ascii_ply},
                                                             {"_binary.ply", &binary_ply}};
  for (const auto& [suffix, ply] : plys) {
    write(dir, std::string("role_x_twice") + suffix,
          replace_nth(*ply, "property double z\n", "property double x\n"));
    write(dir, std::string("role_no_z") + suffix, replace_nth(*ply, "property double z\n", ""));
    write(dir, std::string("role_list_y") + suffix,
          replace_nth(*ply, "property double y\n", "property list uchar double y\n"));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds OUTDIR\n");
    return 2;
  }
  try {
    const std::string dir = argv[1];
    const foldfill::Mesh mesh = holed_sheet();
    foldfill::write_mesh(mesh, dir + "/seed_sheet.obj");
    foldfill::write_mesh(mesh, dir + "/seed_sheet.off");
    for (bool binary : {true, false}) {
      const std::string name = dir + (binary ? "/seed_sheet_binary" : "/seed_sheet_ascii");
      foldfill::write_mesh(mesh, name + ".ply", {binary});
      foldfill::write_mesh(mesh, name + ".stl", {binary});
    }
    write_variants(dir, mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
