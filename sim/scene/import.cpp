// `file` scenes: glTF / OBJ (anything assimp reads) with base colours, diffuse textures
// (through OpenImageIO, linearised from sRGB), normals and uvs.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <assimp/GltfMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/limits.h"
#include "sim/scene/builtin.h"
#include "sim/scene/scene_keys.h"

namespace fovsim {

namespace {

namespace fs = std::filesystem;

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// A file name as shown in a message: control bytes escaped, at most 200 characters.
std::string printable_name(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s.substr(0, 200)) {
    if (c < 0x20 || c == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02x", c);
      out += b;
    } else {
      out += char(c);
    }
  }
  return out + (s.size() > 200 ? "...\"" : "\"");
}

// %XX decoding of a URI path (glTF URIs are URI-encoded).
std::string uri_decode(const std::string& u) {
  std::string out;
  for (size_t i = 0; i < u.size(); ++i) {
    if (u[i] == '%' && i + 2 < u.size() && std::isxdigit((unsigned char)u[i + 1]) &&
        std::isxdigit((unsigned char)u[i + 2])) {
      out += char(std::stoi(u.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += u[i];
    }
  }
  return out;
}

// A file a model refers to (a glTF buffer or image URI, an OBJ mtllib, a texture): relative,
// without "..", inside the model's folder, and (when present) a regular file within the input
// size limit. Returns the path to read; throws fovsim::Error(where, ...) otherwise.
std::string confined_path(const std::string& dir, const std::string& ref, const std::string& where,
                          const std::string& what) {
  const std::string r = uri_decode(ref);
  if (r.empty()) throw Error(where, what + " reference is empty");
  if (r.find('\0') != std::string::npos || r.find(':') != std::string::npos)
    throw Error(where, what + " " + printable_name(ref) +
                           ": only relative paths inside the model's folder are read");
  fs::path p(r);
  if (p.is_absolute() || r[0] == '/' || r[0] == '\\')
    throw Error(where, what + " " + printable_name(ref) +
                           ": absolute paths are refused (only files inside the model's folder are "
                           "read)");
  for (const auto& part : p)
    if (part == "..")
      throw Error(where, what + " " + printable_name(ref) +
                             ": \"..\" is refused (only files inside the model's folder are read)");
  const std::string full = (fs::path(dir) / p).string();
  // A symbolic-link loop says so (path_kind throws); a link out of the folder is refused.
  if (path_kind(full, where + ": " + what) != PathKind::missing) {
    check_inside(dir.empty() ? "." : dir, full, where, what);
    check_input_file(full, where + ": " + what);
  }
  return full;
}

// The JSON of a .gltf file, or of a .glb file's JSON chunk (glTF 2's binary container and
// glTF 1.0's KHR_binary_glTF put it at byte 20), through the checked parser: syntax errors
// located, nesting bounded (kMaxJsonDepth). nullopt for a .glb without the glTF header (the
// importer then says it is not readable).
std::optional<Json> gltf_document(const fs::path& model, bool glb, const std::string& where) {
  const std::string text = read_file(model.string());
  std::string json = text;
  if (glb) {
    auto u32 = [&](size_t off) {
      uint32_t v = 0;
      std::memcpy(&v, text.data() + off, 4);
      return v;
    };
    if (text.size() < 20 || text.compare(0, 4, "glTF") != 0) return std::nullopt;
    const uint32_t version = u32(4), length = u32(12), type = u32(16);
    if ((version == 1 ? type != 0 : type != 0x4E4F534Au) || length > text.size() - 20)
      return std::nullopt;
    json = text.substr(20, length);
  }
  try {
    Json j = parse_json_text(json, model.string());
    if (!j.is_object())
      throw Error(where, model.string() + ": not a glTF file (the JSON is not an object)");
    return j;
  } catch (const Error& e) {
    if (e.where() == where) throw;
    throw Error(where, std::string("not a glTF file: ") + e.what());
  }
}

// glTF nodes form trees (glTF 2.0 §3.5.3, glTF 1.0 §5.19): every node has at most one parent,
// no cycles, and here at most kMaxNodeDepth levels. Checked breadth-first (no recursion) on
// the JSON before assimp, whose importer, validation and destructor recurse once per level.
// glTF 2 lists nodes in an array with integer children; glTF 1.0 in an object keyed by id.
void check_node_tree(const Json& j, const std::string& file, const std::string& where) {
  if (!j.contains("nodes")) return;
  const Json& nodes = j["nodes"];
  std::vector<const Json*> list;
  std::vector<std::string> names;
  std::map<std::string, size_t> by_id;
  if (nodes.is_array()) {
    for (size_t i = 0; i < nodes.size(); ++i) {
      list.push_back(&nodes[i]);
      names.push_back(std::to_string(i));
    }
  } else if (nodes.is_object()) {
    for (auto it = nodes.begin(); it != nodes.end(); ++it) {
      by_id[it.key()] = list.size();
      list.push_back(&it.value());
      names.push_back(printable_name(it.key()));
    }
  } else {
    return;
  }
  const size_t n = list.size();
  std::vector<std::vector<size_t>> kids(n);
  std::vector<int> parents(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const Json& nd = *list[i];
    if (!nd.is_object() || !nd.contains("children") || !nd["children"].is_array()) continue;
    for (const Json& c : nd["children"]) {
      size_t k = n;  // a reference to no node is the importer's to report
      if (c.is_number_unsigned() && c.get<uint64_t>() < n)
        k = size_t(c.get<uint64_t>());
      else if (c.is_string() && by_id.count(c.get<std::string>()))
        k = by_id[c.get<std::string>()];
      if (k == n) continue;
      if (++parents[k] > 1)
        throw Error(where, file + ": glTF node " + names[k] +
                               " is a child of more than one node (glTF node hierarchies are "
                               "trees)");
      kids[i].push_back(k);
    }
  }
  std::vector<int> depth(n, 0);
  std::vector<size_t> queue;
  for (size_t i = 0; i < n; ++i)
    if (parents[i] == 0) {
      depth[i] = 1;
      queue.push_back(i);
    }
  for (size_t q = 0; q < queue.size(); ++q) {
    const size_t i = queue[q];
    if (depth[i] > kMaxNodeDepth)
      throw Error(where, file + ": node hierarchy nested deeper than " +
                             std::to_string(kMaxNodeDepth) + " levels (glTF node " + names[i] +
                             "; the limit for any model)");
    for (size_t k : kids[i]) {
      depth[k] = depth[i] + 1;
      queue.push_back(k);
    }
  }
  if (queue.size() < n)
    for (size_t i = 0; i < n; ++i)
      if (depth[i] == 0)
        throw Error(where, file + ": glTF node " + names[i] +
                               " is its own ancestor (a cycle in \"children\")");
}

// The files a glTF (buffers, images) or OBJ (mtllib) file names, checked with confined_path
// before assimp opens any of them. glTF "data:" URIs are embedded and need no file.
void check_references(const fs::path& model, const std::string& where) {
  std::string ext = model.extension().string();
  for (char& c : ext) c = char(std::tolower((unsigned char)c));
  const std::string dir = model.parent_path().string();
  if (ext == ".gltf" || ext == ".glb") {
    const std::optional<Json> doc = gltf_document(model, ext == ".glb", where);
    if (!doc) return;
    const Json& j = *doc;
    check_node_tree(j, model.string(), where);
    // glTF 2 lists them in arrays, glTF 1.0 in objects keyed by id (shaders only in 1.0).
    for (const char* list : {"buffers", "images", "shaders"}) {
      if (!j.contains(list) || !(j[list].is_array() || j[list].is_object())) continue;
      const std::string kind = std::string(list) == "buffers"  ? "buffer"
                               : std::string(list) == "images" ? "image"
                                                               : "shader";
      for (const Json& e : j[list]) {
        if (!e.is_object() || !e.contains("uri")) continue;
        if (!e["uri"].is_string())
          throw Error(where, model.string() + ": " + list + "[].uri is not a string");
        const std::string u = e["uri"].get<std::string>();
        if (u.rfind("data:", 0) == 0) continue;
        const std::string f = confined_path(dir, u, where, kind);
        if (kind == "buffer" && path_kind(f, where + ": buffer") == PathKind::missing)
          throw Error(where,
                      "buffer " + printable_name(u) + " of " + model.string() + " not found");
      }
    }
  } else if (ext == ".obj") {
    const std::string text = read_file(model.string());
    size_t pos = 0;
    while (pos < text.size()) {
      size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      std::string line = text.substr(pos, end - pos);
      pos = end + 1;
      size_t i = line.find_first_not_of(" \t");
      if (i == std::string::npos || line.compare(i, 6, "mtllib") != 0) continue;
      std::string rest = line.substr(i + 6);
      size_t a = rest.find_first_not_of(" \t"), b = rest.find_last_not_of(" \t\r");
      if (a == std::string::npos) continue;
      confined_path(dir, rest.substr(a, b - a + 1), where, "material library");
    }
  }
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Colour textures are sRGB-encoded (linearised here); data textures (normal maps) are not.
// An alpha channel (RGBA, or grey + alpha) is kept, linear, for cut-out materials.
void fill_texels(const float* px, int nc, bool srgb, TextureImage& out) {
  const size_t n = out.texels.size();
  const bool has_alpha = nc == 4 || nc == 2;
  if (has_alpha) out.alpha.resize(n);
  auto lin = [srgb](float c) { return srgb ? srgb_to_linear(c) : c; };
  for (size_t i = 0; i < n; ++i) {
    const float* p = &px[i * size_t(nc)];
    glm::vec3 c = nc >= 3 ? glm::vec3(p[0], p[1], p[2]) : glm::vec3(p[0]);
    out.texels[i] = {lin(c.x), lin(c.y), lin(c.z)};
    if (has_alpha) out.alpha[i] = p[nc - 1];
  }
}

// "" when every texel is finite, else why the texture is refused (an EXR may hold NaN or
// infinities; a shaded NaN would reach the scored images).
std::string check_texels(const TextureImage& t) {
  for (size_t i = 0; i < t.texels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(t.texels[i][c]))
        return "texel " + std::to_string(i % size_t(std::max(1, t.width))) + ", " +
               std::to_string(i / size_t(std::max(1, t.width))) +
               " is not finite (NaN or infinity)";
  for (float a : t.alpha)
    if (!std::isfinite(a)) return "an alpha value is not finite (NaN or infinity)";
  return "";
}

// Header checks before any pixel is decoded: a positive size within max_pixels and 1 to 4
// channels. "" when fine, else why not.
std::string check_header(const OIIO::ImageSpec& spec, double max_pixels) {
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
    return "empty image (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) + ")";
  if (spec.nchannels < 1 || spec.nchannels > 4)
    return "expected 1 to 4 channels, got " + std::to_string(spec.nchannels);
  if (double(spec.width) * double(spec.height) > max_pixels)
    return "image header claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
           " pixels, over scene.max_texture_pixels = " + std::to_string(int64_t(max_pixels));
  return "";
}

// Decodes an opened image into texels: "" on success, else why it could not be used. `what`:
// "image" or "embedded image" (the file and the in-memory texture share this one decoder).
std::string decode_opened(std::unique_ptr<OIIO::ImageInput> in, const char* what, bool srgb,
                          double max_pixels, TextureImage& out) {
  if (!in) return std::string("cannot read ") + what + ": " + one_line(OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  std::string why = check_header(spec, max_pixels);
  if (!why.empty()) return why;
  int nc = spec.nchannels;
  std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(nc));
  bool ok = in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, px.data());
  const std::string err = ok ? "" : one_line(in->geterror());
  in->close();
  if (!ok) return std::string("cannot decode ") + what + " (truncated or corrupt): " + err;
  out.width = spec.width;
  out.height = spec.height;
  out.texels.resize(size_t(spec.width) * size_t(spec.height));
  fill_texels(px.data(), nc, srgb, out);
  return check_texels(out);
}

// "" on success, else why the image could not be used.
std::string load_image_file(const std::string& path, bool srgb, double max_pixels,
                            TextureImage& out) {
  QuietStderr quiet;  // libpng's own error line: the error is returned (and printed once)
  return decode_opened(OIIO::ImageInput::open(path), "image", srgb, max_pixels, out);
}

std::string load_image_memory(const aiTexture* t, bool srgb, double max_pixels, TextureImage& out) {
  QuietStderr quiet;
  if (t->mHeight == 0) {  // compressed (png/jpg) bytes in memory
    OIIO::Filesystem::IOMemReader mem(t->pcData, t->mWidth);
    void* ptr = &mem;
    OIIO::ImageSpec config;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &ptr);
    std::string ext = std::string("x.") + (t->achFormatHint[0] ? t->achFormatHint : "png");
    return decode_opened(OIIO::ImageInput::open(ext, &config), "embedded image", srgb, max_pixels,
                         out);
  }
  if (t->mWidth == 0 || double(t->mWidth) * double(t->mHeight) > max_pixels)
    return "embedded image of " + std::to_string(t->mWidth) + "x" + std::to_string(t->mHeight) +
           " texels is empty or over scene.max_texture_pixels";
  out.width = int(t->mWidth);
  out.height = int(t->mHeight);
  out.texels.resize(size_t(t->mWidth) * size_t(t->mHeight));
  std::vector<float> px(out.texels.size() * 4);
  for (size_t i = 0; i < out.texels.size(); ++i) {
    const aiTexel& x = t->pcData[i];
    px[4 * i] = x.r / 255.f;
    px[4 * i + 1] = x.g / 255.f;
    px[4 * i + 2] = x.b / 255.f;
    px[4 * i + 3] = x.a / 255.f;
  }
  fill_texels(px.data(), 4, srgb, out);
  return "";
}

glm::mat4 to_glm(const aiMatrix4x4& m) {
  // assimp is row-major (a1..a4 is the first row); glm is column-major.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4,
                   m.b4, m.c4, m.d4);
}

struct Loader {
  const aiScene* ai = nullptr;
  Scene* s = nullptr;
  std::string dir, where;  // model folder; JSON path of scene.path for messages
  double max_pixels = 0;
  bool fail_on_missing = true;
  std::map<std::string, int> image_index;
  std::vector<int> mesh_map;  // assimp mesh -> Scene mesh

  int image(const std::string& ref, bool srgb = true) {
    const std::string key = ref + (srgb ? "" : "#linear");
    auto it = image_index.find(key);
    if (it != image_index.end()) return it->second;
    TextureImage img;
    std::string why, name = ref;
    if (const aiTexture* emb = ai->GetEmbeddedTexture(ref.c_str())) {
      why = load_image_memory(emb, srgb, max_pixels, img);
    } else {
      // Confined to the model's folder (throws for "..", absolute paths, devices, FIFOs).
      const std::string p = confined_path(dir, ref, where, "texture");
      name = p;
      if (path_kind(p, where + ": texture") == PathKind::missing)
        why = "texture not found";
      else
        why = load_image_file(p, srgb, max_pixels, img);
    }
    const bool ok = why.empty();
    if (!ok) {
      if (fail_on_missing)
        throw Error(where,
                    "texture " + printable_name(name) + ": " + why +
                        " (set scene.on_missing_texture=\"base_color\" to render without it)");
      std::fprintf(stderr,
                   "warning: %s: texture %s: %s; using the base colour "
                   "(scene.on_missing_texture=\"base_color\")\n",
                   where.c_str(), printable_name(name).c_str(), why.c_str());
    }
    int idx = -1;
    if (ok) {
      img.build_mips();  // filtered lookups (texture.cpp)
      s->images.push_back(std::move(img));
      idx = int(s->images.size() - 1);
    }
    image_index[key] = idx;  // a missing texture falls back to the base colour
    return idx;
  }

  void materials() {
    for (unsigned i = 0; i < ai->mNumMaterials; ++i) {
      const aiMaterial* am = ai->mMaterials[i];
      Material m;
      aiString name;
      if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
      aiColor4D c(1.f, 1.f, 1.f, 1.f);
      if (am->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS ||
          am->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
        m.base_color = {c.r, c.g, c.b};
      aiColor3D e;
      if (am->Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) m.emission = {e.r, e.g, e.b};
      float shin = 0.f;
      if (am->Get(AI_MATKEY_SHININESS, shin) == AI_SUCCESS && shin > 1.f) {
        m.shininess = std::min(shin, 512.f);
      }
      // glTF alphaMode: MASK = cut-out at alphaCutoff (rays pass where alpha < cutoff), BLEND =
      // transparent (flagged, not blended), OPAQUE ignores alpha.
      aiString alpha_mode;
      const bool has_mode = am->Get(AI_MATKEY_GLTF_ALPHAMODE, alpha_mode) == AI_SUCCESS;
      const std::string mode = has_mode ? alpha_mode.C_Str() : "";
      float opacity = 1.f;
      const bool has_opacity = am->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS;
      if (mode == "MASK") {
        float cutoff = 0.5f;
        am->Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff);
        m.alpha_cutoff = std::clamp(cutoff, 0.f, 1.f);
        m.alpha = has_opacity ? opacity : c.a;
      } else if (mode == "BLEND" || (!has_mode && has_opacity && opacity < 0.999f)) {
        m.transparent = true;
      }
      // Metallic-roughness (glTF PBR) mapped to Lambert + Blinn-Phong: diffuse albedo
      // base x (1 - metallic); ks = F0 = mix(0.04, luma(base), metallic); Blinn-Phong exponent
      // 2 / a^2 - 2 with a = roughness^2 (the Beckmann/Phong correspondence, Walter et al. 2007),
      // in [1, 512]. Files without these keys keep the defaults (ks 0.04, exponent 32 or
      // the file's shininess).
      float metallic = 0.f, roughness = -1.f;
      const bool has_metal = am->Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
      const bool has_rough = am->Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS;
      if (has_metal || has_rough) {
        metallic = std::clamp(metallic, 0.f, 1.f);
        const float lum =
            0.2126f * m.base_color.x + 0.7152f * m.base_color.y + 0.0722f * m.base_color.z;
        m.specular = 0.04f + (lum - 0.04f) * metallic;
        m.base_color *= 1.f - metallic;
        if (has_rough) {
          const float a =
              std::max(1e-3f, std::clamp(roughness, 0.f, 1.f) * std::clamp(roughness, 0.f, 1.f));
          m.shininess = std::clamp(2.f / (a * a) - 2.f, 1.f, 512.f);
        }
      }
      aiString tex;
      if (am->GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS ||
          am->GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS) {
        int idx = image(tex.C_Str());
        if (idx >= 0) {
          m.tex = TexKind::Image;
          m.image = idx;
        }
      }
      aiString ntex;
      if (am->GetTexture(aiTextureType_NORMALS, 0, &ntex) == AI_SUCCESS) {
        m.normal_image = image(ntex.C_Str(), false);
        float ns = 1.f;
        if (am->Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), ns) == AI_SUCCESS)
          m.normal_scale = ns;
      }
      // Emissive texture: the shading model has one emission colour per material, so the
      // texture enters as its mean (factor x mean texel); the factor alone otherwise.
      aiString etex;
      if (am->GetTexture(aiTextureType_EMISSIVE, 0, &etex) == AI_SUCCESS) {
        const int ei = image(etex.C_Str());
        if (ei >= 0 && !s->images[size_t(ei)].texels.empty()) {
          glm::vec3 mean(0.f);
          for (const glm::vec3& t : s->images[size_t(ei)].texels) mean += t;
          m.emission *= mean / float(s->images[size_t(ei)].texels.size());
        }
      }
      s->materials.push_back(m);
    }
    if (s->materials.empty()) s->materials.push_back(Material{});
  }

  void meshes() {
    mesh_map.assign(ai->mNumMeshes, -1);
    for (unsigned i = 0; i < ai->mNumMeshes; ++i) {
      const aiMesh* am = ai->mMeshes[i];
      if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      Mesh m;
      m.name = am->mName.C_Str();
      m.material = int(am->mMaterialIndex) < int(s->materials.size()) ? int(am->mMaterialIndex) : 0;
      m.positions.resize(am->mNumVertices);
      for (unsigned v = 0; v < am->mNumVertices; ++v)
        m.positions[v] = {am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z};
      if (am->HasNormals()) {
        m.normals.resize(am->mNumVertices);
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
          glm::vec3 n(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
          float l = glm::length(n);
          m.normals[v] = (l > 0.f && std::isfinite(l)) ? n / l : glm::vec3(0, 1, 0);
        }
      }
      if (am->HasTextureCoords(0)) {
        m.uvs.resize(am->mNumVertices);
        for (unsigned v = 0; v < am->mNumVertices; ++v)
          m.uvs[v] = {am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y};
      }
      for (unsigned f = 0; f < am->mNumFaces; ++f) {
        const aiFace& face = am->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points/lines after triangulation
        glm::uvec3 t(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
        if (t.x >= am->mNumVertices || t.y >= am->mNumVertices || t.z >= am->mNumVertices) continue;
        m.triangles.push_back(t);
      }
      if (m.triangles.empty()) continue;
      s->meshes.push_back(std::move(m));
      mesh_map[i] = int(s->meshes.size() - 1);
    }
  }

  // Every node's meshes become objects, in the order of a depth-first pre-order walk (the
  // order of the former recursion), with an explicit stack: no recursion, whatever the depth,
  // and a depth over kMaxNodeDepth (any format, after import) is an error naming the file.
  // Records each node name's world transform (the first node of that name in the walk, as
  // aiNode::FindNode finds it) for the file's lights.
  void nodes(const aiNode* top, const glm::mat4& root, const std::string& file) {
    struct Item {
      const aiNode* n;
      glm::mat4 parent;
      int depth;
    };
    std::vector<Item> stack{{top, glm::mat4(1.f), 1}};
    while (!stack.empty()) {
      const Item it = stack.back();
      stack.pop_back();
      const aiNode* n = it.n;
      if (it.depth > kMaxNodeDepth)
        throw Error(where, file + ": node hierarchy nested deeper than " +
                               std::to_string(kMaxNodeDepth) + " levels (the limit for any model)");
      const glm::mat4 xf = it.parent * to_glm(n->mTransformation);
      node_xf.emplace(std::string(n->mName.C_Str()), xf);
      for (unsigned i = 0; i < n->mNumMeshes; ++i) {
        int mi = n->mMeshes[i] < mesh_map.size() ? mesh_map[n->mMeshes[i]] : -1;
        if (mi < 0) continue;
        Object o;
        o.name = std::string(n->mName.C_Str());
        if (o.name.empty()) o.name = s->meshes[size_t(mi)].name;
        o.mesh = mi;
        o.transform = root * xf;
        s->objects.push_back(o);
      }
      for (unsigned c = n->mNumChildren; c-- > 0;)
        if (n->mChildren[c]) stack.push_back({n->mChildren[c], xf, it.depth + 1});
    }
  }
  std::map<std::string, glm::mat4> node_xf;  // node name -> node-to-model transform
};

// ---- load_file_scene stages

// The model file: relative to the config that wrote `path` (a "base" config's folder for an
// inherited path), else under models/scenes/; checked to be a regular file within the input
// limits whose references stay inside its folder.
fs::path resolve_model_path(Params& p, const std::string& rel, const std::string& models_dir) {
  fs::path path(rel);
  if (!path.is_absolute()) {
    const std::string inherited = p.source_dir("path");
    fs::path base = !inherited.empty() ? fs::path(inherited)
                    : p.file().empty() ? fs::current_path()
                                       : fs::path(p.file()).parent_path();
    fs::path a = base / rel, b = fs::path(models_dir) / "scenes" / rel;
    const std::string w = p.where("path");
    path = path_kind(a.string(), w) != PathKind::missing   ? a
           : path_kind(b.string(), w) != PathKind::missing ? b
                                                           : a;
  }
  if (path_kind(path.string(), p.where("path")) == PathKind::missing)
    throw Error(p.where("path"), "scene file not found: " + path.string());
  check_input_file(path.string(), p.where("path"));
  check_references(path, p.where("path"));
  return path;
}

const aiScene* read_model(Assimp::Importer& imp, const fs::path& path, const std::string& where) {
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_GenSmoothNormals | aiProcess_SortByPType |
                         aiProcess_ValidateDataStructure;
  const aiScene* ai = imp.ReadFile(path.string(), flags);
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    std::string why = imp.GetErrorString();
    // assimp says "No suitable reader found" when no importer recognises the content (a
    // corrupt .glb, a binary file named .obj): say that, naming the file and its extension.
    if (why.find("No suitable reader found") != std::string::npos)
      why = "its contents are not a readable " +
            (path.extension().empty() ? std::string("model") : path.extension().string()) +
            " file (malformed or truncated; no importer recognises them)";
    else if (why.empty())
      why = "the importer returned an incomplete scene";
    throw Error(where, "cannot import " + path.string() + ": " + escape_control(why, 300));
  }
  return ai;
}

// translate x rotate (x, then y, then z) x scale: applied to the whole model.
glm::mat4 root_transform(const FileSceneKeys& k) {
  const std::vector<double>&tr = k.translate, &rot = k.rotate_deg;
  glm::mat4 root(1.f);
  root[3] = glm::vec4(float(tr[0]), float(tr[1]), float(tr[2]), 1.f);
  glm::quat q = glm::angleAxis(float(deg2rad(rot[2])), glm::vec3(0, 0, 1)) *
                glm::angleAxis(float(deg2rad(rot[1])), glm::vec3(0, 1, 0)) *
                glm::angleAxis(float(deg2rad(rot[0])), glm::vec3(1, 0, 0));
  root = root * glm::mat4_cast(q);
  root[0] *= float(k.scale);
  root[1] *= float(k.scale);
  root[2] *= float(k.scale);
  return root;
}

// Lights from the file (point/spot/directional), in world space.
// `node_xf`: each node name's node-to-model transform (Loader::nodes; no recursive FindNode).
void add_file_lights(const aiScene* ai, const glm::mat4& root,
                     const std::map<std::string, glm::mat4>& node_xf, Scene& s) {
  for (unsigned i = 0; i < ai->mNumLights; ++i) {
    const aiLight* al = ai->mLights[i];
    Light l;
    const auto n = node_xf.find(std::string(al->mName.C_Str()));
    const glm::mat4 xf = n != node_xf.end() ? root * n->second : root;
    glm::vec3 pos =
        glm::vec3(xf * glm::vec4(al->mPosition.x, al->mPosition.y, al->mPosition.z, 1.f));
    glm::vec3 dir =
        glm::vec3(xf * glm::vec4(al->mDirection.x, al->mDirection.y, al->mDirection.z, 0.f));
    if (glm::length(dir) < 1e-6f) dir = {0, -1, 0};
    glm::vec3 col(al->mColorDiffuse.r, al->mColorDiffuse.g, al->mColorDiffuse.b);
    float mx = std::max(col.x, std::max(col.y, col.z));
    if (!(mx > 0.f)) continue;
    l.color = col / mx;
    l.intensity = mx;
    l.position = pos;
    l.direction = glm::normalize(dir);
    if (al->mType == aiLightSource_DIRECTIONAL) {
      l.type = Light::Type::Directional;
    } else if (al->mType == aiLightSource_SPOT) {
      l.type = Light::Type::Spot;
      l.spot_inner_deg = float(rad2deg(al->mAngleInnerCone));
      l.spot_outer_deg = float(rad2deg(al->mAngleOuterCone));
    } else if (al->mType == aiLightSource_POINT) {
      l.type = Light::Type::Point;
      // glTF point intensities are candela (W/sr-like); our point light is I / d^2 too.
    } else {
      continue;
    }
    s.lights.push_back(l);
  }
}

// A key light (directional, shadowed) from above-front-right and a fill point light, placed
// by the model's world bounds (centre `ctr`, radius `radius`).
void add_default_lights(Scene& s, const glm::vec3& ctr, float radius) {
  Light key;
  key.type = Light::Type::Directional;
  key.direction = glm::normalize(glm::vec3(-0.4f, -1.f, -0.6f));
  key.intensity = 2.5f;
  key.shadows = true;
  s.lights.push_back(key);
  Light fill;
  fill.type = Light::Type::Point;
  fill.position = ctr + glm::vec3(-1.5f, 1.2f, 2.0f) * radius;
  fill.intensity = 0.6f * glm::dot(fill.position - ctr, fill.position - ctr);
  fill.shadows = false;
  s.lights.push_back(fill);
}

}  // namespace

// Stages: the keys (file_scene_table), the model path, assimp's import, materials and meshes
// (Loader), the root transform, lights (the file's or the defaults), the viewpoint.
Scene load_file_scene(Params& p, const std::string& models_dir) {
  const FileSceneKeys k = file_scene_table().read(p);
  p.ignore("comment");
  const fs::path path = resolve_model_path(p, k.path, models_dir);
  Assimp::Importer imp;
  const aiScene* ai = read_model(imp, path, p.where("path"));

  Scene s;
  s.name = path.stem().string();
  Loader L;
  L.ai = ai;
  L.s = &s;
  L.dir = path.parent_path().string();
  L.where = p.where("path");
  L.max_pixels = k.max_texture_pixels;
  L.fail_on_missing = k.on_missing_texture == "fail";
  L.materials();
  L.meshes();
  const glm::mat4 root = root_transform(k);
  L.nodes(ai->mRootNode, root, path.string());
  if (s.objects.empty()) throw Error(p.where("path"), "no triangles in " + path.string());

  // World bounds, for default lights and viewpoint.
  AABB wb;
  for (const Object& o : s.objects)
    for (const glm::vec3& v : s.meshes[size_t(o.mesh)].positions)
      wb.extend(glm::vec3(o.transform * glm::vec4(v, 1.f)));
  glm::vec3 ctr = 0.5f * (wb.lo + wb.hi);
  float radius = std::max(1e-3f, 0.5f * glm::length(wb.hi - wb.lo));

  add_file_lights(ai, root, L.node_xf, s);
  if (s.lights.empty() && k.default_lights) add_default_lights(s, ctr, radius);
  s.ambient = glm::vec3(0.06f);
  s.background = glm::vec3(0.05f, 0.05f, 0.07f);
  s.exposure = k.exposure;
  const std::vector<double>& eye = k.default_eye;
  if (eye.size() == 3)
    s.default_eye = {float(eye[0]), float(eye[1]), float(eye[2])};
  else  // in front of the model (+z), far enough to see it whole with a ~90 deg FOV
    s.default_eye = ctr + glm::vec3(0, 0, 1.3f * radius);
  return s;
}

}  // namespace fovsim
