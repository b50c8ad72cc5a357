#pragma once
/// @file mitsuba_xml.h
/// Reading Mitsuba 3 XML documents (pugixml): the document with its $parameters substituted and ids
/// resolved, element paths with line numbers for messages, and the typed properties of one plugin.
/// The scene mapping itself is in common/formats/mitsuba/scene_mitsuba.cpp and common/formats/mitsuba/mitsuba_bsdf.cpp.
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "common/util/math.h"

namespace firstshot::mitsuba {

/// One XML scene file being read. Parsing substitutes every `$name` in attribute values by the
/// `<default name=… value=…>` of the scene, upgrades Mitsuba 0.x property names (camelCase →
/// snake_case, as Mitsuba 3 does for version < 2) and indexes the elements that have an `id`.
class Document {
 public:
  /// Parses @p text. @throws InputError naming @p file and the line and column of malformed XML,
  /// a missing `<scene version=…>` or an undefined `$name`.
  Document(std::string file, const std::string& text);
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;

  const std::string& file() const { return file_; }
  pugi::xml_node scene() const { return doc_.child("scene"); }

  /// The element's path ("scene/shape[3]/bsdf", a property by its name, an index only where a tag
  /// repeats, counted from 1) and its line: "scene/shape[3]/bsdf (line 12)".
  std::string where(pugi::xml_node node) const;
  /// The path without the line, for names kept in the scene (ShapeDesc::name, MaterialDesc::name).
  std::string path(pugi::xml_node node) const;
  [[noreturn]] void fail(pugi::xml_node node, const std::string& message) const;

  /// While alive, one more level of bsdfs or textures inside one another; @throws InputError past 16 levels
  /// (a `<ref>` cycle, or absurd nesting), instead of recursing without end.
  class Nested {
   public:
    Nested(Document& doc, pugi::xml_node node);
    ~Nested() { --doc_.nesting_; }
    Nested(const Nested&) = delete;
    Nested& operator=(const Nested&) = delete;

   private:
    Document& doc_;
  };

  /// The element with `id` @p id, or an empty node.
  pugi::xml_node byId(const std::string& id) const;
  /// Follows a `<ref id=…>` to its target (@throws InputError if there is none); other nodes as they are.
  pugi::xml_node resolve(pugi::xml_node node) const;

  /// Keeps "file: message" for flush() the first time @p key is noted in this document (one line per
  /// kind of approximation, not one per element).
  void note(const std::string& key, const std::string& message);
  /// Counts a property or element the mapping does not read (one line for all of them, by flush()).
  void ignore(pugi::xml_node node) { ignored_.push_back(path(node)); }
  /// How a `<texture type="bitmap">` becomes a constant colour where one is taken (Plugin::color): set by the scene
  /// reader, which finds its file (common/formats/mitsuba/mitsuba_texture.h: the image's mean). Unset: 0.5 grey, noted.
  void setBitmapMean(std::function<Color(pugi::xml_node)> f) { bitmapMean_ = std::move(f); }
  /// Prints the notes, then "file: N properties not used by firstshot, skipped (the first ones)", on stderr.
  /// Called once the scene is read: a scene refused with an InputError prints its one error line only.
  void flush();

 private:
  void substitute();
  void upgradeNames();
  int line(pugi::xml_node node) const;

  std::string file_;
  pugi::xml_document doc_;
  std::vector<size_t> lineStarts_;  ///< byte offset of each line's first character
  std::map<std::string, pugi::xml_node> ids_;
  std::map<const void*, int> index_;  ///< each element's place among its parent's children of its tag, from 1
  int nesting_ = 0;
  std::set<std::string> noted_;
  std::vector<std::string> notes_;
  std::vector<std::string> ignored_;
  std::function<Color(pugi::xml_node)> bitmapMean_;
  friend class Plugin;
};

/// The properties of one plugin element (`<shape type="…">`, `<bsdf …>`, …): its children with a
/// `name` (values, transforms, named textures or references) and its unnamed nested plugins. Each is
/// read at most once; finish() counts what was not read as ignored.
class Plugin {
 public:
  Plugin(Document& doc, pugi::xml_node node);
  /// Counts the unread properties and nested elements as ignored (Document::ignore).
  void finish();

  Document& doc() const { return doc_; }
  pugi::xml_node node() const { return node_; }
  /// The `type` attribute. @throws InputError if missing.
  const std::string& type() const { return type_; }
  bool has(const char* name) const { return named_.count(name) != 0; }
  /// The named child @p name (marked read), or an empty node.
  pugi::xml_node take(const char* name);
  /// The unnamed nested plugins with tag @p tag (`<ref id>` followed to such elements), marked read.
  std::vector<pugi::xml_node> nested(const char* tag);

  double number(const char* name, double fallback);      ///< `<float>` or `<integer>`
  int integer(const char* name, int fallback);           ///< `<integer>`
  bool boolean(const char* name, bool fallback);         ///< `<boolean value="true|false">`
  std::string string(const char* name, const std::string& fallback);  ///< `<string>`
  Vec3d point(const char* name, const Vec3d& fallback);  ///< `<point>` or `<vector>`: value="x, y, z" or x=… y=… z=…
  /// A colour: `<rgb>` ("r, g, b", or one value), `<srgb>` (gamma-encoded "r, g, b" or "#rrggbb", linearised),
  /// `<spectrum>` (one value: grey; wavelength:value pairs or `type="blackbody"` through the CIE observer,
  /// common/color/spectrum_rgb.h: a reflectance, or an emission inside an `<emitter>`), Mitsuba 0.6's `<blackbody>`,
  /// `<float>`, or a texture by its mean (a bitmap's image, Document::setBitmapMean; a checkerboard's two colours;
  /// both noted). Never negative.
  Color color(const char* name, const Color& fallback);
  /// `<transform name=…>`: translate, rotate, scale, matrix and lookat in document order (each
  /// applied after the ones before it). Identity when absent.
  Mat4d transform(const char* name);

 private:
  Color colorOf(pugi::xml_node node);
  Color srgbColor(pugi::xml_node node);      ///< `<srgb>`, linearised
  Color spectrumColor(pugi::xml_node node);  ///< `<spectrum>` or `<blackbody>`

  Document& doc_;
  pugi::xml_node node_;
  std::string type_;
  std::map<std::string, pugi::xml_node> named_;
  std::vector<pugi::xml_node> unnamed_;
  std::set<std::string> readNamed_;
  std::set<size_t> readUnnamed_;
};

/// A name for a scene element kept in the scene (ShapeDesc::name, LightDesc::name): its path, and its id if it has one.
std::string elementName(const Document& doc, pugi::xml_node node);

/// Numbers separated by commas and/or white space in the attribute @p attr of @p node (exactly
/// @p count of them when count > 0). @throws InputError naming the element.
std::vector<double> numbers(const Document& doc, pugi::xml_node node, const char* attr, size_t count = 0);

}  // namespace firstshot::mitsuba
