#pragma once
/// An OBJ's materials, read here rather than by OpenMesh's OBJ reader (which opened whatever a
/// `mtllib` line named with a blocking open, so that a named pipe or /dev/zero made it wait or grow
/// for ever, and which took a `map_Kd` line's options for the file name). Material libraries are
/// read through read_input_file (regular files only, within kMaxMaterialFileBytes).
#include <string>

namespace sdm {

/// The texture of the OBJ `text` (the file `obj_path`): the map_Kd of the textured material that
/// the most faces use (`usemtl`), the first textured one when no face names one; resolved beside the
/// material library, absolute and normalised; "" when there is none. A library that does not exist
/// is skipped, as is a material without map_Kd.
/// \throw InputError when a library or the chosen
/// texture exists but is not a regular file, or a library is larger than the limit.
std::string obj_texture(const std::string& text, const std::string& obj_path);

/// The file a map_Kd line names after its options (-s 1 1 1, -o u v w, -bm 1, -clamp on, -blendu on,
/// ...), with Windows separators ('\') turned into '/'; "" when it names none.
std::string map_file_name(const std::string& arguments);

/// Makes `text` an OBJ that OpenMesh's reader takes as meant, bytes and lines in place: `mtllib`
/// lines become comments (obj_texture reads the materials) and a comment after a line's values
/// becomes blanks (OpenMesh read '# comment' after a face's corners as more corners).
void prepare_obj_for_openmesh(std::string& text);

}  // namespace sdm
