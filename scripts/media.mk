# Large procedural media, made on demand (included by the top-level Makefile).
#   make media                  every medium below, into $(MEDIA_DIR)
#   make media/twill512.vdb     one of them
#   make previews               docs/previews/*.png, one per kind (rendered by vdb_render)
# Files depend on the generator binary: a rebuilt vdb_make_medium remakes them.

MEDIA_DIR ?= media
MAKE_MEDIUM = $(BUILD_DIR)/bin/vdb_make_medium
RENDER = $(BUILD_DIR)/bin/vdb_render
PREVIEW_SPP ?= 32
PREVIEW_LIGHTS = --env 0.3 --sun 1,0.6,-1.2,3

LARGE_MEDIA = \
  $(MEDIA_DIR)/twill512.vdb \
  $(MEDIA_DIR)/twill512_cube.vdb \
  $(MEDIA_DIR)/satin512.vdb \
  $(MEDIA_DIR)/velvet256.vdb \
  $(MEDIA_DIR)/hairy-ball256.vdb \
  $(MEDIA_DIR)/hairy-ball256_two.vdb \
  $(MEDIA_DIR)/cloud256.vdb \
  $(MEDIA_DIR)/exemplars128.vdb

media: build $(LARGE_MEDIA)

$(MEDIA_DIR)/twill512.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) twill --res 512 -v -o $@
$(MEDIA_DIR)/twill512_cube.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) twill --res 512 --layers 4 -v -o $@
$(MEDIA_DIR)/satin512.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) twill --pattern satin --yarns 5 --res 512 -v -o $@
$(MEDIA_DIR)/velvet256.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) velvet --res 256 -v -o $@
$(MEDIA_DIR)/hairy-ball256.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) hairy-ball --res 256 -v -o $@
$(MEDIA_DIR)/hairy-ball256_two.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) hairy-ball --res 256 --two-materials -v -o $@
$(MEDIA_DIR)/cloud256.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) cloud --res 256 -v -o $@
$(MEDIA_DIR)/exemplars128.vdb: $(MAKE_MEDIUM)
	@mkdir -p $(@D) && $(MAKE_MEDIUM) exemplars --res 128 --count 8 --layout 16x16 -v -o $@

# One preview per kind, from a medium made in memory and piped (nothing left on disk), rendered by
# vdb_render from the side that shows it best, under a sky and a low sun.
PREVIEW_KINDS = twill satin velvet hairy-ball hairy-ball-two cube sphere slab cloud exemplars
preview_args_twill = twill --res 192
preview_args_satin = twill --pattern satin --yarns 5 --res 192 --warp-albedo 0.9,0.85,0.75 --weft-albedo 0.2,0.2,0.5
preview_args_velvet = velvet --res 160
preview_args_hairy-ball = hairy-ball --res 192
preview_args_hairy-ball-two = hairy-ball --res 192 --two-materials
preview_args_cube = cube --res 96 --variation 0.8 --albedo 0.9,0.5,0.2 --density 30
preview_args_sphere = sphere --res 96 --variation 0.8 --albedo 0.3,0.6,0.9 --density 30
preview_args_slab = slab --res 96 --variation 0.8 --density 30
preview_args_cloud = cloud --res 160
preview_args_exemplars = exemplars --res 64 --count 4

previews: build
	@mkdir -p docs/previews
	@for kind in $(PREVIEW_KINDS); do \
	  case $$kind in \
	    twill) args="$(preview_args_twill)";; satin) args="$(preview_args_satin)";; \
	    velvet) args="$(preview_args_velvet)";; hairy-ball) args="$(preview_args_hairy-ball)";; \
	    hairy-ball-two) args="$(preview_args_hairy-ball-two)";; cube) args="$(preview_args_cube)";; \
	    sphere) args="$(preview_args_sphere)";; slab) args="$(preview_args_slab)";; \
	    cloud) args="$(preview_args_cloud)";; exemplars) args="$(preview_args_exemplars)";; \
	  esac; \
	  case $$kind in twill|satin|exemplars|slab) view=+z;; *) view=-y;; esac; \
	  echo "previews: vdb_make_medium $$args | vdb_render --view $$view -> docs/previews/$$kind.png"; \
	  $(MAKE_MEDIUM) $$args -o - | $(RENDER) - --view $$view --res 288 --spp $(PREVIEW_SPP) --seed 1 \
	    $(PREVIEW_LIGHTS) -o docs/previews/$$kind.png || exit 1; \
	done

.PHONY: media previews
