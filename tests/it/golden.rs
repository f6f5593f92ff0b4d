//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (each render is its own
//! test, named after it, and its failure prints the render's new lines of the table). Updated once on purpose since: when every transcendental function on the
//! output path moved from the host's C library to the pure-Rust `libm` (issue 20, item 10),
//! which changed last bits (the bunny's frame 0 at 320×240: 306 of 7.77 M queries flipped).
//! Since then these hashes hold on any host whatever its C library. Updated on purpose again
//! for issue 22: the EXR's channels renamed (`shadow.rays`, …) with depth, normal and albedo
//! passes and a header (camera matrices, settings, counts), and the PNGs made through a view
//! transform (AgX by default) and tagged sRGB — every EXR and PNG changed, and the validated
//! renders' stats.csv, whose PSNR is now measured on the AgX previews.
//! The EXR hashes changed once more when every EXR gained its alpha channel `A` (issue 22: all
//! ones over these opaque backgrounds; every other channel, the PNGs and the statistics kept
//! their bits).
//! And once more when the header gained the `[lights] scene_lights` setting (issue 24: the
//! file's own lights; its attribute `envshadow/lights.scene_lights`), the rest unchanged.
//! And with glTF materials (issue 24): the bunny's material (metallic 0, roughness 1) has the
//! rough dielectric's specular, so every bunny EXR and PNG and the validated renders'
//! stats.csv changed; the other stats.csv, every lights.json and the shapes' PNGs (Lambertian)
//! kept their bits, and the EXR headers list the `[render] glossy_env` setting. The bunny
//! rendered with `--lambert` has the PNGs, stats.csv and lights.json of `bunny-brute` before
//! materials.
//! And once more for issue 38's shading rate: every EXR header gained the `[render]
//! shading_rate` setting (its pixels unchanged: `idiff` finds no difference against the
//! previous build's), the four-sample frames render at the sample rate as before, and the
//! pixel rate, the new default, has renders of its own.

use crate::common;

use std::path::Path;

use sha2::{Digest, Sha256};

/// One render through the binary: a name, the spec (relative to the repository) and its flags.
struct Render {
    name: &'static str,
    spec: &'static str,
    flags: Vec<String>,
}

/// The bunny at a quarter of its size: what every method is checked on.
const BUNNY: &str = "anims/bunny-turntable.toml";
const SMALL: &str = "--width 320 --height 240";

fn render(name: &'static str, spec: &'static str, flags: &str) -> Render {
    Render {
        name,
        spec,
        flags: flags.split_whitespace().map(String::from).collect(),
    }
}

fn renders() -> Vec<Render> {
    let mut v = vec![
        // The default animation's first frames at one sample per pixel, as the README's
        // first command rendered them before samples per pixel; then at four samples, as it
        // renders them now (recorded when samples per pixel came).
        render(
            "shapes-turntable",
            "anims/shapes-turntable.toml",
            "--frames 0..3 --spp 1",
        ),
        render(
            "shapes-turntable-spp4",
            "anims/shapes-turntable.toml",
            "--frames 0..2 --spp 4 --shading-rate sample",
        ),
        // The same frames at the pixel shading rate, the default since issue 38: Lambertian
        // samples are shaded alone at either rate, so their files are the sample rate's but
        // for the EXR header's `shading_rate`.
        render(
            "shapes-turntable-spp4-pixel",
            "anims/shapes-turntable.toml",
            "--frames 0..2 --spp 4",
        ),
    ];
    for (name, method) in [
        ("bunny-none", "none"),
        ("bunny-brute", "brute"),
        ("bunny-scan-warp-boundary", "scan-warp-boundary"),
        ("bunny-grid-warp-boundary", "grid-warp-boundary"),
        ("bunny-grid-nowarp-boundary", "grid-nowarp-boundary"),
        ("bunny-grid-warp-uncertainty", "grid-warp-uncertainty"),
        ("bunny-grid-nowarp-uncertainty", "grid-nowarp-uncertainty"),
        // Added after the restructure (its first method beyond the paper's).
        ("bunny-scan-nowarp-uncertainty", "scan-nowarp-uncertainty"),
    ] {
        let flags = format!("{SMALL} --frames 0..2 --method {method}");
        v.push(render(name, BUNNY, &flags));
    }
    for (name, flags) in [
        (
            "bunny-nowarp-all",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to all",
        ),
        (
            "bunny-nowarp-contrary",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-warp-contrary",
            "--frames 0..2 --method grid-warp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-tuned",
            "--frames 1 --h0 8 --min-voters 2 --lights 100 --tile 24",
        ),
        (
            "bunny-scan-block",
            "--frames 1 --method scan-warp-boundary --scan-block 32 --tile 48",
        ),
        ("bunny-validate", "--frames 0..2 --validate"),
        (
            "bunny-validate-warp",
            "--frames 1 --validate --method grid-warp-boundary",
        ),
        (
            "bunny-validate-scan",
            "--frames 1 --validate --method scan-warp-boundary",
        ),
        // Orbit: reprojection. Frames 2..6 start mid-chain, so frames 0 and 1 warm it up.
        (
            "bunny-temporal-orbit",
            "--frames 2..6 --temporal --keyframe 4 --validate",
        ),
        (
            "bunny-temporal-warp",
            "--frames 0..3 --temporal --method grid-warp-uncertainty",
        ),
    ] {
        v.push(render(name, BUNNY, &format!("{SMALL} {flags}")));
    }
    // Lambertian materials keep the bits they had before glTF materials: the bunny with
    // --lambert against bunny-brute's hashes as recorded before materials (its materials,
    // metallic 0 and roughness 1, have had specular since).
    v.push(render(
        "bunny-brute-lambert",
        BUNNY,
        &format!("{SMALL} --frames 0..2 --method brute --lambert"),
    ));
    // The bunny's glTF material shaded once per pixel surface, validated: its reference
    // shaded the same way from the traced bits (issue 38).
    v.push(render(
        "bunny-spp4-pixel",
        BUNNY,
        &format!("{SMALL} --frames 0..2 --spp 4 --validate"),
    ));
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `thread_seconds` column, which is a timing, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr e95e9123a686bb9f985cd4bcf0138474880f8dcbfca9672b8d3818086e6aa497
shapes-turntable frame_0000.png c3d8e47faebbb561990eb64f014492e20b85e580eb125836926deaac81baa03d
shapes-turntable frame_0001.exr a254265e866d93c6a53fb35b1bd18b395d28e6125a7ffa5ca51ee5f2c3ba0196
shapes-turntable frame_0001.png c45cbd9d6299e6080b78a483acdb3511847bd00aa2718ba95cd9a570e2ad8ac2
shapes-turntable frame_0002.exr ba65b693eff80ad7333c70abe0d748e974b50b507d51056f5a97053082421d1f
shapes-turntable frame_0002.png 72c3d398c8493b3618855a6884b64ac34f45c9e2d1b00ca40705831419a4820a
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 01cc4ec6ff2372b71fa37cb4cded5813e834616096e199f96fb3e0c129ed0c15
shapes-turntable-spp4 frame_0000.exr 7d1898ac58977d938f33c5487c8a2ca616924be8d255fd1bf52e67872f32b3ba
shapes-turntable-spp4 frame_0000.png 864d41345e4522d035187fad828fac821c344e870558f9a06b211d82146124dd
shapes-turntable-spp4 frame_0001.exr 8f663250f52939aa68cade11000a77cf8dc471f491512bbb54a78f267adc4841
shapes-turntable-spp4 frame_0001.png f25dcc9c2bf734e6b676ad42b89a3497b4ebb02ee774f2c75feb705b21aaecea
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 2ee9bfa78dd1daf02054adf1bcb79ea44f94a98ef9d7392abfa2fd156f701c20
bunny-none frame_0000.exr 7ebbdbd46bc9ad02c2b927899b6f9a1944c8f3f2c22670ccc1766580e7e3ca6c
bunny-none frame_0000.png 643f65f294962e1da64dc18ae6de02140f59af3a66cc4f483355383ef3e36e1d
bunny-none frame_0001.exr 7d135923f9a72cf9db5ea7064cc80c8148c8646d76af9d3af73b91e79f8ecf8f
bunny-none frame_0001.png b1cb238899da32f68328df4589e3707bd435037e841cdc3bd92fbbcdeef2fc7e
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 58784e8a6058cee25e59722d35ff5872946235113f0f1105a70b1c6334961bb8
bunny-brute frame_0000.png a40349e2f26e212a5c1a0769171627c495be9533f8e5e43bda63b5d1626e8db4
bunny-brute frame_0001.exr 24d4e303c848cfe3cd25609784145c9e1bbd46401bcf9654192606e9aa39b01d
bunny-brute frame_0001.png 43b35e9ff06ca0dd60c7a2a2bf07cdb1d97e8e00f545847a8b5dd15a25e0cd76
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr a2f1fc2ce4d4268ee148efc1f622a6c93e045ee2a537b9f0688a7b2f458677ad
bunny-scan-warp-boundary frame_0000.png b5875f92ae4375335ab2b594a598778ca39a23402cf8f90f6f4aae91f7dd93be
bunny-scan-warp-boundary frame_0001.exr 43364ead88e04e984be0fdafd6ca803d88282fd6b2fa84862610e0eb114f5e19
bunny-scan-warp-boundary frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 9a91c445e193e9da2b5567b68a3f396318f29c6f9777ce0c63316b21c9182959
bunny-grid-warp-boundary frame_0000.exr db7c4f0e47dc12dc59ad9d936b727269473a30fae72594e1eaab28c0256aa2e5
bunny-grid-warp-boundary frame_0000.png 1577c5c33e04e5bc12d95de7b48593bf15ce7bacd2e82d79fed46f4dcb58dbcb
bunny-grid-warp-boundary frame_0001.exr b0ee87edaa785575c4c3c57f1d90c595c25c81ad175377a8cc44fdc95ff29986
bunny-grid-warp-boundary frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv aa2bf7c47bf449e1328eede03814407a420a85cb7407600377ea6c32a69c3b91
bunny-grid-nowarp-boundary frame_0000.exr dc7c3b85d874589481ba7f92d82bb52b6e7c29baa2c7ce93f9588a6dfdb09bd5
bunny-grid-nowarp-boundary frame_0000.png a5e790ebc14ba6df03278b88f589a0aa81ca7e431fd02f48eba8335d84d2c598
bunny-grid-nowarp-boundary frame_0001.exr f92edd63d53333d266443503d33ec4f6c8d1ba8ffb784024a3149c8f56cb2197
bunny-grid-nowarp-boundary frame_0001.png bcbc04c59ae34e2918111818eb66cbc4751b331df498309024284697c2699a29
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 4e2c57cea6dc9b82fbb3c0f0fb89d68763d418cc91b07c6b59541ad43e1ffa25
bunny-grid-warp-uncertainty frame_0000.exr 9fd24a27a1d7496b4689a90dbef72e2fc74031f2b7e27ebf0711ad92615202d8
bunny-grid-warp-uncertainty frame_0000.png 7085633a355c4b6489361cb9ca9a38b7dfaa1560fbcfcc827f7bac02d44689ce
bunny-grid-warp-uncertainty frame_0001.exr 84b85a75d8f84afdf72e9d8914d6b39bdf15724435f94877cb7a14f69bab743e
bunny-grid-warp-uncertainty frame_0001.png 86f3248e7450e98fdddb29f30a307100626ed8371910d20119a1072eb5b2b3cc
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv 15d6d0f55d9e8e62b36865b5e7e5ec49de07a25c395d7e4d3d145878e411312f
bunny-grid-nowarp-uncertainty frame_0000.exr 2129efa2554f2248c00b6ed2f647c079c32f52bfef6265ebacc58978dc4c4257
bunny-grid-nowarp-uncertainty frame_0000.png e98ccc5d7e3a6dc7e546b8b7d9fbb7d3a31bc0fab9e83bb0bdd7cb6af7f36e9d
bunny-grid-nowarp-uncertainty frame_0001.exr b391372b12f9dfcc5119dcc19ba5df8ca85c0cb5adf771de78878bbe1b52ed38
bunny-grid-nowarp-uncertainty frame_0001.png ef412762b9601fc6358900db55474181b5c6391c2fea3af6f983290fd3935256
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv b06e222a66b76d6c20a0e2dcf748c37c1ef72aa860390b0d655393255100746f
bunny-scan-nowarp-uncertainty frame_0000.exr c49fa4cdff9b88da38193a469d0dfda362fc56d4dde78edc00d00233bec78977
bunny-scan-nowarp-uncertainty frame_0000.png 4161372d609609adae2538c34551c6a4de0b850c05e58b24ab43a7979d8b739d
bunny-scan-nowarp-uncertainty frame_0001.exr abd75befca3be9275f63af20e160382d9dce16ed8328f579f6070d8a00137138
bunny-scan-nowarp-uncertainty frame_0001.png f8ea4886b2b651ef0e150d3fab4a241e44c6fe1ed5a26b3d641c47535aaeaad6
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 91fd060eaa65a54a47ffd0b4224faa77c67a4f010538666186422b76587bee56
bunny-nowarp-all frame_0000.exr 71a03644f6682ac090d975877cc66c7e726a26074617c2ff842e4fcec35012d1
bunny-nowarp-all frame_0000.png 71bc907594e64ad7bde3665b2a882e4663046d931d32a90557600feb21e81628
bunny-nowarp-all frame_0001.exr 0b7e2c0506cbb3fbc00f5a48a8e166a52f762324a51a09621a295df7f6e0c1f5
bunny-nowarp-all frame_0001.png a510e905cfa8c9a1643b6ecbfea80472561bbf343544a033bd01dcfc8ec9808d
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv fd951dece046206b16da8fe8ccdb54c43fb34f6f5ef7ae9f1ebb49a1e9deca81
bunny-nowarp-contrary frame_0000.exr 87a631e68ecb3d84528e4ddb934a48efeb7c2d7fd4b7e0c1d0d161d34b645c3b
bunny-nowarp-contrary frame_0000.png 21942eaf65090481fc6430e42941103f23c9cab7b43189b9fba6f83b68defa3b
bunny-nowarp-contrary frame_0001.exr 47f53e815af6e19a8185cd07f79f615f7710b8ff382047edf5e3279b0d58ccd3
bunny-nowarp-contrary frame_0001.png d47aaca9ab1d7aea6fed399d8f8a370e5a5b5435e522fe48987f36cd06848c17
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv ae451332f58af1cdbcb22210e860ab0c524ed7702cad28313aff3d4cf19c2bd9
bunny-warp-contrary frame_0000.exr 9de5073923a62b8c5e8dc3b4aa2b8cef78bde45e7728c7295e70c48c35571d8e
bunny-warp-contrary frame_0000.png 7683291a8b85517127f170d7af2f1522b138e7375707832994675cd3efc16575
bunny-warp-contrary frame_0001.exr 504c0e1f05f8cc3c693b692b5b81c3af12f9273a8239f3c193ecdb8ec919022d
bunny-warp-contrary frame_0001.png 6e066d51831786a925eb937725581c0146f76f504b010125a534e5479830b587
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv b07a37cfd09572776a54f1c0c2d4d42a818a01cb3c713865e29abfc3b706c126
bunny-tuned frame_0001.exr 83b3103874625b571328924cc09bb33e32f7810ebc76141d81b23b480c52b23f
bunny-tuned frame_0001.png d123a9878b78174a17cad2e6bf93effda02fc4341a7bbf684635fd65ba14b34d
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv faf2475238baedcb9f492cf522e443cbd7b03d44b42b93eef8bbab17bde2473c
bunny-scan-block frame_0001.exr 438349960e42d162a45e9ef4da2430d5cbb5a4b3d9fd43b91162932e675f4b17
bunny-scan-block frame_0001.png fc31d8715dd95eb33d953ece63fdaa73cb2075d32fe6ffebc218327914bfa0ba
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv f98ef6c8eda859fde763d085d27aae55e6456cd89010e8a05ed9c27adc32a64b
bunny-validate frame_0000.exr 071b680ff4ffe4b76d3632fb7e6b58abe5b78c566cc74c064128d18bdb123c57
bunny-validate frame_0000.png e98ccc5d7e3a6dc7e546b8b7d9fbb7d3a31bc0fab9e83bb0bdd7cb6af7f36e9d
bunny-validate frame_0001.exr 119e15ac0cb2092e4c3b1a7da39efa0c181095d87e54a0cdda6c9679d4a31afd
bunny-validate frame_0001.png ef412762b9601fc6358900db55474181b5c6391c2fea3af6f983290fd3935256
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 717b7d283c401494fe82797978d5d8a5fc171bc4408da573cfdc318b463c2b63
bunny-validate-warp frame_0001.exr ba355bd83cbc7dce5a9a4108c8d7fb4d4ef6c9787fc24429e17d0d31ea55ab85
bunny-validate-warp frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 467cf7670e72521c5b48e76ff3aefb58b83e085375382580428226363cccc99f
bunny-validate-scan frame_0001.exr bac5874f03a25d902d8ac249724e9320254b0804b38a5933b2d41b1ce98d4e77
bunny-validate-scan frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 0a91cb5193527f9ba17ec361bb93a13c3e4012e75d0a617b85b7692e20d56526
bunny-temporal-orbit frame_0002.exr fbf8f814de8ed4966af5199f8d633d74f4e50263595a4da1ec796ea8e19a50c9
bunny-temporal-orbit frame_0002.png dbfcd7e573569930f1b4437f137a9e51388a168ccfceba5eda9adc40e9696c38
bunny-temporal-orbit frame_0003.exr 0e09bde41af1d5c9322a3bd8538715a9d2ce26cedfd2bd0e0152376a28b8135a
bunny-temporal-orbit frame_0003.png b55c3b7396cd2a78bd75a0787c45cfa465e73a18182a3fe92627e9eceb7abca9
bunny-temporal-orbit frame_0004.exr 9b9138617b9062a89176ee2d087376180ebc3284debca3a5cee395176e91562c
bunny-temporal-orbit frame_0004.png 710bf59243d362444651c9eae7e0f2f1ca7db9b9512d5fe7e368bec76cbc1277
bunny-temporal-orbit frame_0005.exr 18001dedaab43cb2c2306e8a154f0dd8c1c55ff6e33981b9ed973b2f4cb0fef9
bunny-temporal-orbit frame_0005.png 9498a7400a70b5c501f81249cd5a4bdbb56163c9bff6a590754b509a72b5f58c
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv e440494d921d420864e6b1cad66dc09309f4549220faf3f0823fa0d6ec73c08b
bunny-temporal-warp frame_0000.exr 2d9ddfb3b0c84c7849ede4ee324fd429b4f5e7bf008bffd78d1f45931a4b560d
bunny-temporal-warp frame_0000.png 7085633a355c4b6489361cb9ca9a38b7dfaa1560fbcfcc827f7bac02d44689ce
bunny-temporal-warp frame_0001.exr 17ea27c30dcbe44449078f5ae3937f3b5d3d8bb6f7ca8e68a1c018962db0db6b
bunny-temporal-warp frame_0001.png 772970b8f84f09af23ef134bcfce7597471e88b9e99979082dc0fc5cc4ec0d0e
bunny-temporal-warp frame_0002.exr 6b0de07bfff6b9d7c467ed6214f8e36864b0d07580133448e16fa36232de1a38
bunny-temporal-warp frame_0002.png 645966dd78586d66b0306cd0a9ab5d47f2e2a7e0b6ae1367f2fbabc3043c470c
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 4ab0ff830d3161814a2b6f7157f3a326143d115652b78ed8e8fd6e79534d2702
bunny-brute-lambert frame_0000.exr b60ea9c12182fa5751d2d9c9d5356c04a79020395fbdcc4ca9e43ec0b5a827ff
bunny-brute-lambert frame_0000.png ee648a99eb3f1b3129bab45f64dcfa09c3de1cb9711595a4ec51b1462c72f6ca
bunny-brute-lambert frame_0001.exr 5ecaff2b271fd11ea905e335f1056d9ba1cfee66300577f0eee73b22f195fce2
bunny-brute-lambert frame_0001.png d81e4b8d6a073bf3881c7a34f7d26cb29a3274c97c196b6d9b5016d7335b8f00
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-temporal-spin frame_0000.exr ab39c6eebfd83685a8e7998b164a659884402eb2a1cc797c715778a40b630096
bunny-temporal-spin frame_0000.png b654ad58c5e9f00c5c9b361994c170eddbb0ccb7e2d47d59ba7411812f8adcc5
bunny-temporal-spin frame_0001.exr 7c9e62b640973da538340fbd54b64d9681c0b62c71c6aa2929c2432382d0b986
bunny-temporal-spin frame_0001.png 8c42427562ff654d0ab1c1a81b3af58cca26c8fad799b5174aaf41b766e5b66c
bunny-temporal-spin frame_0002.exr 09fa28a1aeb9e7598dbe2cc231d6cba96d37275ffa1bc51d4d760320c459bc29
bunny-temporal-spin frame_0002.png 784f88143309b4ddbb8f6cfb12c6e137635abb99df8e2ab9823c7a3d51716042
bunny-temporal-spin frame_0003.exr 56fc1f4e3e6c4f3f8577ecd947bb6fc68501a1f175e6aaa9fbf74b4824a4a769
bunny-temporal-spin frame_0003.png 44741f50124cf4c7759d8e9347d5b407baec77974bfba443d55a0aa5ebd97b52
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv f65a1fc55b9244ca2fded2012fa6605fc4952f05fca18ec38d431b3fa067515e
bunny-spp4-pixel frame_0000.exr 9d8f5184b7cfc2ec2dde124362a951374f60f4a903411367f1bfae51b1edb555
bunny-spp4-pixel frame_0000.png 3e0154dcbe51968852e6acd3af60c631a722e74f48ff46bf99971ef4d1e7073f
bunny-spp4-pixel frame_0001.exr fa89d5dca027e2805c4b5b0faa5bc4edf31c659b77712b092a04c028ccfbf9dd
bunny-spp4-pixel frame_0001.png 104f849c7599fab50636e0853ba0151db1ef0c92dfe1d6eb5c3c7b40d5691989
bunny-spp4-pixel lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-spp4-pixel stats.csv 9da58012d688f4ab7e39591abf2a1de325e5e6c090f78d54124a3674b74dc9b2
shapes-turntable-spp4-pixel frame_0000.exr 32fa8103ed020b3de6fc21c8f85c024377ad27164b39d924d79b80a3b9591921
shapes-turntable-spp4-pixel frame_0000.png 864d41345e4522d035187fad828fac821c344e870558f9a06b211d82146124dd
shapes-turntable-spp4-pixel frame_0001.exr cb6d1ad84c7d58e01bd26df27d6da9571b5382c473d7620d674f038344bc6f62
shapes-turntable-spp4-pixel frame_0001.png f25dcc9c2bf734e6b676ad42b89a3497b4ebb02ee774f2c75feb705b21aaecea
shapes-turntable-spp4-pixel lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4-pixel stats.csv 2ee9bfa78dd1daf02054adf1bcb79ea44f94a98ef9d7392abfa2fd156f701c20
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `thread_seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "thread_seconds")
        .expect("stats.csv has a thread_seconds column");
    assert_eq!(
        header.pop(),
        Some("spp"),
        "stats.csv ends with the spp column"
    );
    let mut out = format!("{}\n", header.join(","));
    for line in lines {
        let mut f: Vec<&str> = line.split(',').collect();
        f[col] = "";
        assert_eq!(f.pop(), Some(spp), "a golden render at {spp} spp: {line}");
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

/// The output files of one render folder (frames, lights, stats), hashed, in name order.
/// `lights.json` names the map it came from: the assets folder is hashed as `ASSETS`, so the
/// hashes do not depend on where the repository and its assets are. The bookkeeping for
/// `--resume` (`settings.txt`, `records/`) is not output.
fn hashes(dir: &Path, assets: &str, spp: &str) -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "settings.txt" && dir.join(n).is_file())
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            let h = if n == "stats.csv" {
                sha(stats_without_seconds(&String::from_utf8(bytes).unwrap(), spp).as_bytes())
            } else if n == "lights.json" {
                sha(String::from_utf8(bytes)
                    .unwrap()
                    .replace(assets, "ASSETS/")
                    .as_bytes())
            } else {
                sha(&bytes)
            };
            (n, h)
        })
        .collect()
}

/// One `#[test]` per render of [`renders`], named after it: a render that fails names itself,
/// and the others still run (in parallel).
macro_rules! golden {
    ($($test:ident: $name:literal,)*) => {
        $(
            #[test]
            fn $test() {
                keeps_its_bits($name);
            }
        )*
        /// The renders the tests above check, in the order of [`renders`].
        const TESTED: &[&str] = &[$($name),*];
    };
}

golden! {
    shapes_turntable: "shapes-turntable",
    shapes_turntable_spp4: "shapes-turntable-spp4",
    shapes_turntable_spp4_pixel: "shapes-turntable-spp4-pixel",
    bunny_none: "bunny-none",
    bunny_brute: "bunny-brute",
    bunny_scan_warp_boundary: "bunny-scan-warp-boundary",
    bunny_grid_warp_boundary: "bunny-grid-warp-boundary",
    bunny_grid_nowarp_boundary: "bunny-grid-nowarp-boundary",
    bunny_grid_warp_uncertainty: "bunny-grid-warp-uncertainty",
    bunny_grid_nowarp_uncertainty: "bunny-grid-nowarp-uncertainty",
    bunny_scan_nowarp_uncertainty: "bunny-scan-nowarp-uncertainty",
    bunny_nowarp_all: "bunny-nowarp-all",
    bunny_nowarp_contrary: "bunny-nowarp-contrary",
    bunny_warp_contrary: "bunny-warp-contrary",
    bunny_tuned: "bunny-tuned",
    bunny_scan_block: "bunny-scan-block",
    bunny_validate: "bunny-validate",
    bunny_validate_warp: "bunny-validate-warp",
    bunny_validate_scan: "bunny-validate-scan",
    bunny_temporal_orbit: "bunny-temporal-orbit",
    bunny_temporal_warp: "bunny-temporal-warp",
    bunny_brute_lambert: "bunny-brute-lambert",
    bunny_spp4_pixel: "bunny-spp4-pixel",
    bunny_temporal_spin: "bunny-temporal-spin",
}

/// The recorded table as (render, file, hash) lines.
fn expected() -> Vec<(&'static str, &'static str, &'static str)> {
    EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0], f[1], f[2])
        })
        .collect()
}

/// Every render has its test and every recorded line its render: a render added to
/// [`renders`] without a test, or lines left in the table for none, fail here.
#[test]
fn every_render_has_its_test_and_every_recorded_hash_its_render() {
    let names: Vec<&str> = renders().iter().map(|r| r.name).collect();
    assert_eq!(
        names, TESTED,
        "golden! lists every render of renders(), in order"
    );
    let orphans: Vec<String> = expected()
        .into_iter()
        .filter(|(r, _, _)| !names.contains(r))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .collect();
    assert!(orphans.is_empty(), "recorded for no render: {orphans:?}");
}

/// Renders `name` of [`renders`] through the binary and compares the hashes of its files with
/// its lines of the recorded table.
fn keeps_its_bits(name: &str) {
    let r = renders()
        .into_iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("{name}: not in renders()"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
    let out = tmp.path().join(r.name);
    // The specs name their files under ../assets; point them at the test assets.
    let text = std::fs::read_to_string(root.join(r.spec)).unwrap();
    let spec = tmp.path().join(format!("{}.toml", r.name));
    let dir = format!("{}/", assets.display());
    std::fs::write(&spec, text.replace("../assets/", &dir)).unwrap();
    let o = common::bin()
        .args(["render", "-q", "--no-report"])
        .arg(&spec)
        .args(&r.flags)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}: {}",
        r.name,
        String::from_utf8_lossy(&o.stderr)
    );
    let spp = r
        .flags
        .iter()
        .position(|f| f == "--spp")
        .map_or("1", |k| r.flags[k + 1].as_str());
    let got = hashes(&out, &dir, spp);
    let table: String = got
        .iter()
        .map(|(f, h)| format!("{} {f} {h}\n", r.name))
        .collect();
    let expected: Vec<(&str, &str)> = expected()
        .into_iter()
        .filter(|(n, _, _)| *n == r.name)
        .map(|(_, f, h)| (f, h))
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|(f, h)| !expected.contains(&(f.as_str(), h.as_str())))
        .map(|(f, _)| format!("{}/{f}", r.name))
        .chain(
            expected
                .iter()
                .filter(|(e, _)| !got.iter().any(|(f, _)| f == e))
                .map(|(f, _)| format!("{}/{f} (missing)", r.name)),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{}: {} file(s) changed: {}\nits new lines of the table:\n{table}",
        r.name,
        changed.len(),
        changed.join(", ")
    );
}
