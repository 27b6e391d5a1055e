# The scenes of scripts/same-images.sh, sourced by it and by the scripts that render the same
# scenes for other proofs (scripts/sample-dimensions-proof.sh), so that the list is written once.
# Needs `top` (the repository) set by the includer.
# The built-in Cornell box, tests/data/emissive_quad.gltf, the showcase scenes/materials.gltf
# (SAME_IMAGES_SHOWCASE=FILE in its place), and the scenes of
# scripts/make_same_images_scenes.py: glossy, textured, alpha-masked and blended,
# environment-map-lit, punctual-lit and background-lit.
SAME_IMAGES_SCENES=(builtin gltf showcase glossy textured alpha environment punctual background)

# Writes the generated scenes into WORK/scenes, and the environment map (the Cornell box's
# ceiling light, a sharp peak) rendered once with BINARY.
# Usage: same_images_make_scenes BINARY WORK
same_images_make_scenes() {
  python3 "$top/scripts/make_same_images_scenes.py" "$2/scenes"
  "$1" render --width 32 --height 16 --spp 4 --seed 5 -o "$2/scenes/environment.exr" >/dev/null 2>&1
}

# Appends the arguments that name scene NAME (one of SAME_IMAGES_SCENES) to the caller's
# array `args`. Usage: same_images_scene_args NAME WORK
same_images_scene_args() {
  case $1 in
    builtin) ;;
    gltf) args+=("$top/tests/data/emissive_quad.gltf") ;;
    showcase) args+=("${SAME_IMAGES_SHOWCASE:-$top/scenes/materials.gltf}") ;;
    environment)
      args+=("$2/scenes/open.gltf" --environment "$2/scenes/environment.exr"
        --environment-strength 3 --environment-rotation 30) ;;
    background) args+=("$2/scenes/open.gltf" --background 0.4,0.5,0.7) ;;
    *) args+=("$2/scenes/$1.gltf") ;;
  esac
}
