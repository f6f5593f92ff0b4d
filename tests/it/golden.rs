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
shapes-turntable frame_0000.exr 64ce02a5df4cda0489b94ff966af0558ba464d99735944a7dd2bf1e776fa92d2
shapes-turntable frame_0000.png 229848133558b63e882681db556fa934ee6c92884d05a0dc8ad5997c78b0efc5
shapes-turntable frame_0001.exr 0a995e0ed3133192193af92b2ff79af55955b6c958fff11830df26ddbc9a81d7
shapes-turntable frame_0001.png da5127720b0363fd79c4f28ba14444c1e0db52e91d6931921cca55e0655c3255
shapes-turntable frame_0002.exr 1aad7a5413f12f99d26298106605ae7a55b2fb82e953401bcf9ab060053f600b
shapes-turntable frame_0002.png 4bbc97fb00d661f0d4fc16f377c0b8443c1917fe44a21fa04bee26ed30a4c517
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 01cc4ec6ff2372b71fa37cb4cded5813e834616096e199f96fb3e0c129ed0c15
shapes-turntable-spp4 frame_0000.exr a96a1c0745ef3273366edc8c344061b705b269b00efd08ab2abe4db72bb8277e
shapes-turntable-spp4 frame_0000.png 45f6737d91b0c4fde36fd91b18dabff331b84caf39fa36e45f8df0dbbe059123
shapes-turntable-spp4 frame_0001.exr 5683ac8f799d4db8320e7cd8809a1f74f12d72779047aeeae6e71d11dc54ed19
shapes-turntable-spp4 frame_0001.png 55aabad517e91c714f55e09ffde5d547b6f56732b57d54a0aa3e13a8701a6076
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 2ee9bfa78dd1daf02054adf1bcb79ea44f94a98ef9d7392abfa2fd156f701c20
bunny-none frame_0000.exr 856966d53f5001805df8a0d24d064b602a3224aa78e8e30b836de9b786bde17e
bunny-none frame_0000.png 1f186438920637cc04e8892c5e6e859f8fbc6df972cf9dadc4390e62f80ba15d
bunny-none frame_0001.exr 3fedc1c4b33b1141362c4658de65c91134b238e7360d94023d652a8b2d0752a4
bunny-none frame_0001.png 03de3b63caa72093f0e34e953f74b1cef5266657eae24e857e99014687cd1932
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 9e4fd23cc659b30ce81115a5c7b3429683f30ccea4377636e9898f386c89ee7b
bunny-brute frame_0000.png b44e188bbaa261c46c8728159f8632c4e90e0b8d469bdaa5f58b7c14a46d3910
bunny-brute frame_0001.exr 40313b64de08261396de923c6ee8f110f677471b4261349185cb1b183c4eec1b
bunny-brute frame_0001.png 3c6212bb8e3121d9a66a2f17ddda451d039007dfcb4e41e6cd79037904616e90
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr 7f1a87d854dff5ce831ddc8595833d29d449b589b573c6597f081f4243cec098
bunny-scan-warp-boundary frame_0000.png 4f8e20d0cbc05c923f7c9ec34927ae16edba5150ca199c41f53019d8a1636be4
bunny-scan-warp-boundary frame_0001.exr 8f0a996d338fbc5f007e3c7fac0f8ae83e6163dea0a302432edef53420cc06df
bunny-scan-warp-boundary frame_0001.png 4e3c946ab4986685f608eba2ef9f14f71d04ba37e580b709735dd27b513f3218
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 9a91c445e193e9da2b5567b68a3f396318f29c6f9777ce0c63316b21c9182959
bunny-grid-warp-boundary frame_0000.exr bacd120f54926d80e85dd9ac61f5797fe6b97cc7128611be36ea36d083b56cdc
bunny-grid-warp-boundary frame_0000.png be9920c2865868234cad466646757e07880c8d2519cb94aad5442f011c6a5247
bunny-grid-warp-boundary frame_0001.exr 92e320ed18aa1db35f825f0dc757f114fea2befe026cb21efbcadb1dfe2891f7
bunny-grid-warp-boundary frame_0001.png 73c2dedf8628560dd38b66ebf1c0fe35f8fcece2b74bfeef0020fdf17cf44e86
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv aa2bf7c47bf449e1328eede03814407a420a85cb7407600377ea6c32a69c3b91
bunny-grid-nowarp-boundary frame_0000.exr 085acf4aaa107225f128cee8cb2d82d8da604087f71c6f03a2591c4d8fa4d4ab
bunny-grid-nowarp-boundary frame_0000.png d96a9f804db7583b25cd17510327a02b4f7241a9ea769c0087bf8ade5decbc39
bunny-grid-nowarp-boundary frame_0001.exr 4749ead50dc2308579839f6379573228951a3a3752dd95d4ce48d273b3fcaffa
bunny-grid-nowarp-boundary frame_0001.png 7d61c8499d1e1a9e8d768105360f70b95ea80dedd4fb12717c2e9c04aba683cc
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 4e2c57cea6dc9b82fbb3c0f0fb89d68763d418cc91b07c6b59541ad43e1ffa25
bunny-grid-warp-uncertainty frame_0000.exr 83da25e15c65e0e95760733582d95c2e15fac55248f72fd45862224507eee622
bunny-grid-warp-uncertainty frame_0000.png 7a63b6b54e725ccd24856a81e4ad4a5f87c3ebb5684f0d6f6085cb2baca1536f
bunny-grid-warp-uncertainty frame_0001.exr 2cd4fc9d74d91d04efdd244a6d4633610165abe155dfda5cfc5025a6914a9038
bunny-grid-warp-uncertainty frame_0001.png 626391c4ca3344c811c4e130aa42f844a7054bc173ca4a28770e99a65c370a93
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv 15d6d0f55d9e8e62b36865b5e7e5ec49de07a25c395d7e4d3d145878e411312f
bunny-grid-nowarp-uncertainty frame_0000.exr 44e3eb05b1d239fa9d97af9491dffce6de4b1532212f6ab91d8824942fdae414
bunny-grid-nowarp-uncertainty frame_0000.png 2c6981205b9b800669be94fd4ad2b90255c19a12fa49525658468e9118332b0a
bunny-grid-nowarp-uncertainty frame_0001.exr 742e33ee3d28f2cbf5fd91eef7113edd81dc7e69f18907b5ea8d8a2825f456bf
bunny-grid-nowarp-uncertainty frame_0001.png cecbccb0cc4882a759b13519f14cc026af201334f215ffdea120aa7a4202b11f
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv b06e222a66b76d6c20a0e2dcf748c37c1ef72aa860390b0d655393255100746f
bunny-scan-nowarp-uncertainty frame_0000.exr ba1a1dcf3092ae515d6c6b9288d121f5eab0e6fda725ba0622f7088e62112ae8
bunny-scan-nowarp-uncertainty frame_0000.png 7a1a50bf5c3058ef2e9ede845fabcae4ba23b08f2dcd115b76fd10d34de174b2
bunny-scan-nowarp-uncertainty frame_0001.exr 9a61a6b91c12b47767ee2670f9b14d080c75dfcf135066cfa30a0857e9c25577
bunny-scan-nowarp-uncertainty frame_0001.png c0f866f5b68136c967d9ff9a0c60965f095b6fc03a309513bc65609e875e172f
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 91fd060eaa65a54a47ffd0b4224faa77c67a4f010538666186422b76587bee56
bunny-nowarp-all frame_0000.exr 10603c7111d28360cb1dd78ed09f10cfd5e5d9846a5be285c0cc3a3d8f3bd9a8
bunny-nowarp-all frame_0000.png 6a8c791fc9fd1f1a8fa88b8ac0f1d49bac9c22b6827aae5781b4067d2d54e1c0
bunny-nowarp-all frame_0001.exr 3db13ae06640027fc63852987488c1c8667ed8beac5fb3641a129e7b3b72d844
bunny-nowarp-all frame_0001.png 56c0617c689a6e7dadbef2b592178f58df7a074ba249d2e4d10654a4db5e2145
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv fd951dece046206b16da8fe8ccdb54c43fb34f6f5ef7ae9f1ebb49a1e9deca81
bunny-nowarp-contrary frame_0000.exr 2cc12081e114c7b7e03e3dc628758dd4d11f0ed8cbec482ea4eb38246a295236
bunny-nowarp-contrary frame_0000.png e5bb56add9677c59cd5fbe306c58341de7277355d3b2b4e5780e0e8b4170fdcd
bunny-nowarp-contrary frame_0001.exr edbf264ff6f6336f594149ac1f3f1e27ed9e0c0fead97136a0c2021b74892439
bunny-nowarp-contrary frame_0001.png 17228032551af341fb3c10dbec5af6aa423fa89dbf69acc30ce667d60100442f
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv ae451332f58af1cdbcb22210e860ab0c524ed7702cad28313aff3d4cf19c2bd9
bunny-warp-contrary frame_0000.exr fd4623da24179f9f3bf02e8aa1bc7b6ef0abb28fb2d0bf8658e33cd89cd1d2fc
bunny-warp-contrary frame_0000.png 94f1b34e585bab83c3cc19334886b070aa03175047fa39f971272d68483173c8
bunny-warp-contrary frame_0001.exr 89ed43287ac448509de881f420d6bafbcccf6ef494143f10cb6f89d50f0fbc7e
bunny-warp-contrary frame_0001.png 8a4b4b4a011db57e05518c12e91098917ecbec71a798f1be7913e774c85ae56c
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv b07a37cfd09572776a54f1c0c2d4d42a818a01cb3c713865e29abfc3b706c126
bunny-tuned frame_0001.exr cf00b8998b80f8dfd2c9bdb708974ad942d530accb268f5d392dead571b75e9f
bunny-tuned frame_0001.png 6300ff599eaa0dd0d5eadf2e0bcda09ea9babf99ca2989af32d05a534122a325
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv faf2475238baedcb9f492cf522e443cbd7b03d44b42b93eef8bbab17bde2473c
bunny-scan-block frame_0001.exr 71e3dc4ff4e0e513509b89f02ee5049812346bbc0205fcdeb3598830e9e97fe7
bunny-scan-block frame_0001.png 190491fd4c752cf6415fcc1fed2ec97cc3a9e546de88fb84823dbdc9bcbc52e6
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv f98ef6c8eda859fde763d085d27aae55e6456cd89010e8a05ed9c27adc32a64b
bunny-validate frame_0000.exr 616fe98b6789c3c92a23b0845f578c98fa8109606460bdad4eb6e5fd6a353327
bunny-validate frame_0000.png 2c6981205b9b800669be94fd4ad2b90255c19a12fa49525658468e9118332b0a
bunny-validate frame_0001.exr c810201a266c4fc044341a9f047e63231f637286581407129538a5e254806cca
bunny-validate frame_0001.png cecbccb0cc4882a759b13519f14cc026af201334f215ffdea120aa7a4202b11f
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 18e10d850cbaccd370e36930bd4c24a39b4e954741fe50855713687cf9be0e17
bunny-validate-warp frame_0001.exr e69e4016e29cc364bceba37eb9788c9b00de28833d8e08a507e394d8b333ba41
bunny-validate-warp frame_0001.png 73c2dedf8628560dd38b66ebf1c0fe35f8fcece2b74bfeef0020fdf17cf44e86
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 83cc4c7dfe5c2d41cac2f5446f5d88c8a6897f7d04e03b26c809dd03810694ee
bunny-validate-scan frame_0001.exr ad8d42997116e1e6842d535e192fd15f601a1f812f006f40227cbd447ba5e8dc
bunny-validate-scan frame_0001.png 4e3c946ab4986685f608eba2ef9f14f71d04ba37e580b709735dd27b513f3218
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 4ca76f02c23e86de1a6d7abe0d4cfaf2fe2851359112fde542c0df1d32cc35fa
bunny-temporal-orbit frame_0002.exr 9c5c19d9c30c6c6d98d5fcb7fedd261cfecc030c3ccc9433e7cfa7a5983f2d68
bunny-temporal-orbit frame_0002.png d94cedb866924ee77c8a8a8e4192347d7cc842077779e22a810e629639f0187e
bunny-temporal-orbit frame_0003.exr 4dbd00992baf647ba6a22e5899b340ef56c287ea8cf924a16698768426e6b4ec
bunny-temporal-orbit frame_0003.png 569aa452b9bfa807fb89de9efdeca12f0cba7de40a13aaac35e59706c10233dc
bunny-temporal-orbit frame_0004.exr aeb6899a7d99d7bec763c3e96742bf4e47e5f4b3ec4e0b010eadc0ed9d318043
bunny-temporal-orbit frame_0004.png 3ab245ebde92e683d6ea3526d763902f5a8b2bfcf6318d5d7ea31d2f8e9c7b9b
bunny-temporal-orbit frame_0005.exr e67986228b944145b8e4c6cc6d9c09b20c81bb2e6d6bd6d7d82d11f0caafc42c
bunny-temporal-orbit frame_0005.png 7c038e2c983ea23d069b07abf3828029ee504f9d20c6e5862cca2536731ee023
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 811f882396938eba640ec4220dc357a94fa6ebe268bcdc713a5d2f6f5766a00d
bunny-temporal-warp frame_0000.exr 1f0929a7823f19e3bd027d14eb89ea4f22120b7eb9e79dba9db15ac3fd3a47b8
bunny-temporal-warp frame_0000.png 7a63b6b54e725ccd24856a81e4ad4a5f87c3ebb5684f0d6f6085cb2baca1536f
bunny-temporal-warp frame_0001.exr e4db82a368e3e5602620171fca91b039e281e08ffc7675edb28471efc8748f32
bunny-temporal-warp frame_0001.png 54d1ccd1671a9a362b81fcfd481adb9f303c96326418385f289b36cd283a12fb
bunny-temporal-warp frame_0002.exr 057841eecac3f1c02e83e22ec71ba216b95986ee60a230fee3ffc631d79b0d61
bunny-temporal-warp frame_0002.png bfc2db9c052ba252d5970288c1addd721eb5040c37dc1fd2ac4783c6a8078a20
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 4ab0ff830d3161814a2b6f7157f3a326143d115652b78ed8e8fd6e79534d2702
bunny-brute-lambert frame_0000.exr b68afb634288e230f87a90997dfe7080c3ed70d56a0e0d3d8c33932a7b439fc1
bunny-brute-lambert frame_0000.png 804c01dc113f5e74b199ba7d4294c37c6e484400364145ddf487d4974ce9e31c
bunny-brute-lambert frame_0001.exr fa9ec53028e4994a48eff3fe05b8ef69491f06feffe54d2415f1a92c87a83f68
bunny-brute-lambert frame_0001.png d65fbbc249250ad495ccd262400805172cefa21d3a4487949c50686a82304121
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-temporal-spin frame_0000.exr f3fcddcfa6c6f8dd316d8fe8da4938420d674a501a9155cd135ee80dbeb2a1cb
bunny-temporal-spin frame_0000.png 1f776eac925f737af5ef09a062f70f1f388265a596dd434c1c0d0134aa604e61
bunny-temporal-spin frame_0001.exr 01d410ee9ac694ed40b979493f74b1cdb8b3f07b2b413ebeab834854671d80e2
bunny-temporal-spin frame_0001.png d256c663d35acc2362c27ea263f04764607388615cb6a77eb7b0d5303f182136
bunny-temporal-spin frame_0002.exr a81edde2b876017c07464bbc3cbbdb32ee98c7d5ccfc554f6ff478ca87cbf472
bunny-temporal-spin frame_0002.png c5f80106a6332aeda4b23f0db3cf34a7573569aaf1f8675f1f9910011f42f355
bunny-temporal-spin frame_0003.exr a8512b944a149c134d9771a52a57bf77a412bcd580c564776b07460918d84a61
bunny-temporal-spin frame_0003.png 4e6de9db62180dd6984a7cdf4ce1ccf02d7dc2342f6910bb71fb5e2fea6a71d8
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 3248968d9f5e7f8ad25bfdd7024e886fe303ee88f632116083bc1da2a1b191ec
bunny-spp4-pixel frame_0000.exr be1350545a31d0a9e88ae48370893b11f3ad96b27526f28c7fcbc0d46ef919a8
bunny-spp4-pixel frame_0000.png dfb3532fc8664834d2f3056341fd7874e26faea3e9a046cf4118104833e972cb
bunny-spp4-pixel frame_0001.exr 2d287c1b2b79391c2dc9db9e5ca78c66a6a4b62602544f9c3313e6386574fb06
bunny-spp4-pixel frame_0001.png 6eeb3067d1d7a7faabeca31314da48226d0c981ab694f265ed4de0d9736a8d69
bunny-spp4-pixel lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-spp4-pixel stats.csv 6ae8027ce082136dd5b903983541b5445b161119c205c2f537f47dca3f692b05
shapes-turntable-spp4-pixel frame_0000.exr d98334380f4dc952500951344f33f699e8ff7e3c7c4a0626ebd531bb40e3626d
shapes-turntable-spp4-pixel frame_0000.png 45f6737d91b0c4fde36fd91b18dabff331b84caf39fa36e45f8df0dbbe059123
shapes-turntable-spp4-pixel frame_0001.exr 745b8baecec220af9fe85dd186e2bc52ea67d37fc2decfe51ec86c4948835519
shapes-turntable-spp4-pixel frame_0001.png 55aabad517e91c714f55e09ffde5d547b6f56732b57d54a0aa3e13a8701a6076
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
