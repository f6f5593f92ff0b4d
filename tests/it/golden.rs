//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (the failure prints the
//! whole new table). Updated once on purpose since: when every transcendental function on the
//! output path moved from the host's C library to the pure-Rust `libm` (issue 20, item 10),
//! which changed last bits (the bunny's frame 0 at 320×240: 306 of 7.77 M queries flipped).
//! Since then these hashes hold on any host whatever its C library. The EXR hashes changed
//! once more when every EXR gained its alpha channel `A` (issue 22: all ones over these opaque
//! backgrounds; every other channel, the PNGs and the statistics kept their bits, checked
//! channel by channel against the frames before).

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
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `seconds` column, which is a wall-clock time, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr 6b0d8c530522331d885c53927472926aaf327f968800135711bf2b63b533cfb6
shapes-turntable frame_0000.png 1cbe80db6928cae6252c151ea368e81d6681f0c4d710b4b90db1cfc4bd2a63a3
shapes-turntable frame_0001.exr aad822b8c022dfc4671647854f0365b5ee9a9e0230b60fb6996d02daa157b205
shapes-turntable frame_0001.png 640aaba349e431b8cf26e7b8dfa99be725775606f25c06aa7cc4c1aa3581343b
shapes-turntable frame_0002.exr 562bba920d23a8b04207998104a56c3a9e2efaf3975ec943c96d3ca057f5e53a
shapes-turntable frame_0002.png 7782ce016d8711a540b0bc783d6b6f9d7122a4e38cd79b66c234b9510a0028dc
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 2bc19a8b5090f1005650925550e7a1fa0eb0a8d8ac1490451975b884a4110668
shapes-turntable-spp4 frame_0000.png f2260c5b38912a03fb88474b1d51e8eb32b021de6d2136e99e0214a886eace13
shapes-turntable-spp4 frame_0001.exr 40aee9460268c8f11a56a834a1c6a807b89dbc87c1169a1084007e916dc2bc32
shapes-turntable-spp4 frame_0001.png 9b76d7ca74a34dae4b0dc7c272520cd306f37624b45bfed726758bdbb6ce7293
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr 99fcabecc7787ddc377a1c966eac616aa54d8d0725b48ddfec01c0ddba81c9ac
bunny-none frame_0000.png aa0eef2241793907cb23849ed88b5a865c5d91e0d0afcdc7d5d4463351679993
bunny-none frame_0001.exr 78f27ab81cd7c8d93dc893d6e82b965b3c3563b8085d3e4dd0a09178b56829dd
bunny-none frame_0001.png 69fb927b5716d8f2547425875e2d527408ec04a8eee1e4eb8acde0ace4784a1a
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f2da642e694712dbcb867dfec49916da8b09cfe3fe737ebc55d3bea2ad9bec4b
bunny-brute frame_0000.exr 3ac6cde5e5989777142907a0b6f03642a83d1f25942a2703b1dccbeb34921883
bunny-brute frame_0000.png 38ab726c7a051e7b217cc7dc6128bf9bf10de3d4fe56a5151ddede1affef1b2b
bunny-brute frame_0001.exr 64eba67b3d6f11ce92908f7ce25f967091542ab9bc1dda6720035b91f26c094a
bunny-brute frame_0001.png 00ca72651904f1a277017363da8265f9a72af1d9c6feb3177762b676aa991bc6
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-scan-warp-boundary frame_0000.exr edd0fa2d8ba458585ac98a5c0db6f4bd75d136ae80e0dbff8dbf1488f43fb173
bunny-scan-warp-boundary frame_0000.png d0246a493cd874e2a9015f2fe265b36d823f3c860d3f5a0f8bfba2b2187ba5dd
bunny-scan-warp-boundary frame_0001.exr 8340b32c75ec82ed40e90fecd32ea0aa995f705d7b14870df8e5aa6f85dcaeb4
bunny-scan-warp-boundary frame_0001.png 7e13179f69013b0bfc2372e6fa2f81f52bf94af70337f1f784017e5a49e27963
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 85e705dda9d8539aa40b2a17d9a47a05a5a4ec9f34ec6e2355389ed3bbabe315
bunny-grid-warp-boundary frame_0000.exr d94b5c488b6ba9694d7505da007233b3440006a4c28fb70b719f5859768110b5
bunny-grid-warp-boundary frame_0000.png 841c549e6d947f704333c9e81c40ff2e4fd43382e316a7c9e7f3a9ddd8b28c49
bunny-grid-warp-boundary frame_0001.exr 3d4db6a73b109fca6290bf05642d93420f54bb8a0f64d00e0bb6659bb9b7f832
bunny-grid-warp-boundary frame_0001.png 3e43e502e26f5ad61b732f0e827406a5a02cc258ccc5401c3cb4b4e667ac918c
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv cf291ceba167064918e92c442f0967c92cdb60bf701abcf7eb4e407ce521528a
bunny-grid-nowarp-boundary frame_0000.exr 2b18dc88e6ffc56bb15930b5a297361b923f7c75fa23a813eab6e6896fd08ed0
bunny-grid-nowarp-boundary frame_0000.png 665d54f49d2271139880f269529819797c5b892f274cebdded169ab38158a637
bunny-grid-nowarp-boundary frame_0001.exr 15cc15058d96c2c62b407b0ace480c61c19067efabdfd444eb55ec851b1f1fb3
bunny-grid-nowarp-boundary frame_0001.png d3e691344543826ae9ac6e2ea5a43019a61c764302e9587ee339e5b3c63a540c
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 50ce3e753a666cfca057a41e1eac6b746e4c0121c152def0b0e6bc0c21f30da7
bunny-grid-warp-uncertainty frame_0000.exr 753e284df9ce1a86c6a2b7c2665cdacedc1c92a5d93327556e26661675efef37
bunny-grid-warp-uncertainty frame_0000.png 31fe19fcbf3fad7e3709e0136735bd5647df88dec5e29d61ac425b1bbde58b20
bunny-grid-warp-uncertainty frame_0001.exr a7a08c15ab8ae7bebda044e64aebbad5204c3a0ce2c7859539f0d2106f1da47e
bunny-grid-warp-uncertainty frame_0001.png 7a6bf4eec448091931140f0cbb3cbef3f8e0f602a68258f0a314b92efd89ef98
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d204b31c9e78552d93afb35da486084fdf321244707d9259bb57391bbc29479e
bunny-grid-nowarp-uncertainty frame_0000.exr b33994f91921f29c17bc7bdeb0b8b2f74fb9ee696b32c823fa14f43f4c265076
bunny-grid-nowarp-uncertainty frame_0000.png c7e8621b29e62c2023ba6ae210f791ecc66488303e8da423d615e2b8db3b2f78
bunny-grid-nowarp-uncertainty frame_0001.exr f54c1a318bdc88955c8e13a3775f5dbb04b481b66b564cd42dfd8a3261ce220c
bunny-grid-nowarp-uncertainty frame_0001.png 1040257b95eb1a33f32a930de5f269d40dd1ec4019a099db4c3e5c136c35d2b3
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 52dcc6b93f0df6759dc69301f316556989c104c376de0989b394ee999ec2801e
bunny-scan-nowarp-uncertainty frame_0000.exr aac523ad891b73bad2776188c8eb8bc8fbf0c76fbc83777ae6bd0359749cfc2a
bunny-scan-nowarp-uncertainty frame_0000.png 08c3aa47c7077557c89c342e3ca2d6943e676fa18d06e76fc1d4ffd4408b9a57
bunny-scan-nowarp-uncertainty frame_0001.exr b1c5b0c3c2d2329df34e7144bb685b08e6496886da0c5a22ef049c6c5d619b60
bunny-scan-nowarp-uncertainty frame_0001.png 973e878dc2dfcde0d39ac565c6893c9264d397b130d35c18da9bafc3f95d7937
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv b23b55384c5c4f8318636ee5cd7281cf1fdb7ae0aae4bbff66bd2cf0928c8aa9
bunny-nowarp-all frame_0000.exr 21c17fbdb0499df2e12daaa9be456fd8c6be6c9f2800a23b73d9502f4b210b6f
bunny-nowarp-all frame_0000.png 96103b23cf51625e1125775c1db90631dd638cdebdb760250ebd08f33b0ae17a
bunny-nowarp-all frame_0001.exr 4dd375c61bad542f7e52d286caeaccbb8811cbd54a154dbeef75324500acdd2a
bunny-nowarp-all frame_0001.png 0785ef97a9b1020669935c4617e56672b1f8c52ce2e08bd3a372cdb7457e37d0
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv c35dbd5906f633061660959526fd7e00ddd26c47b7440d557fc9cc0240f7d76e
bunny-nowarp-contrary frame_0000.exr e162536c4514823ddc45d5774ae5c5cc24f22c82cfd1402b444e754e30cd61aa
bunny-nowarp-contrary frame_0000.png 8b07e090db92a9809d3ae88e9926116cd9ad9dcbe185f9ff9eb42587c704e897
bunny-nowarp-contrary frame_0001.exr 13378835ed9d1e8deb88d5e0c1c72b84a5eaa0576543a8d83b0bf65fbd5e4018
bunny-nowarp-contrary frame_0001.png c261f431051ae5968cdd8f0294c83a05aa506e31c8f57c3ea4e9a723094282d7
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 68d99b20ceb44db79e87162568af23ee9af87e41026a427be6a13feb96ad0395
bunny-warp-contrary frame_0000.exr e617b9b8a3adb82ad11e1d8848628e39600b50f109e7ef568cfb0067bde6049b
bunny-warp-contrary frame_0000.png 1275dc70254273933f8b4df80c011feb8f930685a0dd1ec812c00f0f5487213a
bunny-warp-contrary frame_0001.exr 9362ed4f404fb872bf790ccb656e475917f1061edcdd6fe43813fde0fbb0db5e
bunny-warp-contrary frame_0001.png f4da0a518d258bd3d37683f204c3b90f5cbc468e795fd20e9f172372378353f6
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 6a80d3d5122f34b66f6d1c0a198f92c5d4d97e296a99ec8d2a70bb147d51406b
bunny-tuned frame_0001.exr 1d999a9153eccb6b906797c169d8eec4e3ec06857641a610b4c16445c7117af7
bunny-tuned frame_0001.png f6658ec6b7460d62c83691d59c83be22d1533171c3e158604069a37db8bf56cb
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr ec6c99b3de37895bfa4b8b4859fed400c30f63fd808a544ef0d433c774f4c1e0
bunny-scan-block frame_0001.png 0f868d30a3dd7e041c885eb57dffb459c632b879a7c20e2f14cfd700093398b4
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 894fdcd38d971118b4fc635b79a56626e20f72f00a72d065dee8f05017b2d58b
bunny-validate frame_0000.exr 131dc8dd3733515f448ae830720d22f73e7607706f312da48499dd0448532049
bunny-validate frame_0000.png c7e8621b29e62c2023ba6ae210f791ecc66488303e8da423d615e2b8db3b2f78
bunny-validate frame_0001.exr 4b88bf6f13c0fbd2af601a085a98c2e269754b7ba5d98bfd6f77fb61e0660136
bunny-validate frame_0001.png 1040257b95eb1a33f32a930de5f269d40dd1ec4019a099db4c3e5c136c35d2b3
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv f2ce11864d6675204fbe9a2205a65ff3104deb4df3bfc0601c3927f4b55069e5
bunny-validate-warp frame_0001.exr 847b0009056bc230ac2e3e63e04c00a24bc8df7cb570e2008040a581b819d880
bunny-validate-warp frame_0001.png 3e43e502e26f5ad61b732f0e827406a5a02cc258ccc5401c3cb4b4e667ac918c
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 13192e9e125a58edc6c74aa1f46fbf4f1250a8fc5be3570c303ba9779234b2be
bunny-validate-scan frame_0001.exr b97dd2a977455ac8aaf9c5d603b66af502af36c5ab2ea7a09f237e3d33e8b0c6
bunny-validate-scan frame_0001.png 7e13179f69013b0bfc2372e6fa2f81f52bf94af70337f1f784017e5a49e27963
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 31b9cc7372f274334cd2c92ce6fc71482412138e8248c26ee87a5e5c0666831a
bunny-temporal-orbit frame_0002.exr 528c6126684405b7f849e8e3bf46134d0ec96cbd511051d9a8aa53959ac644cb
bunny-temporal-orbit frame_0002.png d384e257e000fb0342d632899b0a0de2925de4af71a273807f39e9b0e42af9bb
bunny-temporal-orbit frame_0003.exr 1c2282ecb741fb60c7d5e689718321a738647913be227c87abedf55ceeda472c
bunny-temporal-orbit frame_0003.png fdcd7730593cff47522760f837aeae6f16d87a7d4a28a66286aebaec69208260
bunny-temporal-orbit frame_0004.exr fdb9ad5a1ecfa69c15413fab1c98426cd42480f4a5ce14078401a69508c07a8a
bunny-temporal-orbit frame_0004.png 4964d9000e91c1d5b05dc0645228599be680e4fdc7b1f8c7c8b46798aaf722ea
bunny-temporal-orbit frame_0005.exr 1bf3d7c1fefe7eed3424e15d54f5c3e8bf9f071510b4a06314f0879d65385cc6
bunny-temporal-orbit frame_0005.png cdbc624f13cca2731c96345767686fa49654c0beba90c33a88cd316d6fc7429b
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv b83578beb861c2e98b9202a7d2038b39153e0ea3193d1305eec75fbf7153dc14
bunny-temporal-warp frame_0000.exr 753e284df9ce1a86c6a2b7c2665cdacedc1c92a5d93327556e26661675efef37
bunny-temporal-warp frame_0000.png 31fe19fcbf3fad7e3709e0136735bd5647df88dec5e29d61ac425b1bbde58b20
bunny-temporal-warp frame_0001.exr 9511487b622e332748366554c81e4c5788d4d92b92f0e0cb460e901b1f288186
bunny-temporal-warp frame_0001.png e04a5965a94e3142dc6eaf934f21bf5079aa5e0231a3338490d588bda91eaec2
bunny-temporal-warp frame_0002.exr 6264eb05902002271b0721a92a605557af2eebbde7772c394c73bb2f62b171bb
bunny-temporal-warp frame_0002.png 2988a01f4beb8e7a6cb94d053a57591b002b863fd5b5d55ab5fa22a336649116
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 5ec83275df1b4d20ac5e883b5d27caf1c1b80db1cb4ef9b89c5f41b980fd39a0
bunny-temporal-spin frame_0000.exr 6ce3029d82513be72c67f4855a256c5c0aec1afa83cda830a105ced1674aec4a
bunny-temporal-spin frame_0000.png 96d2340bd0cb3f0cbdd683157c72414f6684f8674e9b7aa05395fe86597820ea
bunny-temporal-spin frame_0001.exr 21f8b7cdaaffe94301b2a44434f1919fd32411a7a26085213f0db2d5e552bf60
bunny-temporal-spin frame_0001.png 0062c776ea2d435844cd5a5d9f444c39fd062c42ce40af9b55cd7fdfc8760ae4
bunny-temporal-spin frame_0002.exr ae1a3c66b98790081c14b86841ec5b8d2ee6f25204c356306230043d05d35018
bunny-temporal-spin frame_0002.png f0fe1affe0248707c8ffa039adae94acd2cd4f064f919b62bd34ffacd2634f42
bunny-temporal-spin frame_0003.exr 6b81db56460ffc15b3da9086c996f6a837d0353ce409025f1047b5134f7ecd36
bunny-temporal-spin frame_0003.png 10125a9187fec8dd73438cfb4ed8f8c81099fcec1bd52331bb3c4da3a8971a11
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 182f1457ae78d5034ac30df083ab6116e1a54230523ac1cdeb93df63154cd420
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "seconds")
        .expect("stats.csv has a seconds column");
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

#[test]
fn every_recorded_frame_keeps_its_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
    let mut got: Vec<(String, String, String)> = Vec::new();
    for r in renders() {
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
        for (file, h) in hashes(&out, &dir, spp) {
            got.push((r.name.to_string(), file, h));
        }
    }
    let table: String = got
        .iter()
        .map(|(r, f, h)| format!("{r} {f} {h}\n"))
        .collect();
    let expected: Vec<(String, String, String)> = EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0].to_string(), f[1].to_string(), f[2].to_string())
        })
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|g| !expected.contains(g))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .chain(
            expected
                .iter()
                .filter(|e| !got.iter().any(|g| g.0 == e.0 && g.1 == e.1))
                .map(|(r, f, _)| format!("{r}/{f} (missing)")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{} file(s) changed: {}\nthe new table:\n{table}",
        changed.len(),
        changed.join(", ")
    );
}
