# Sourced by the MAVLink flight scripts (after setting `here` and `passphrase`): BIN_DIR and
# OUT_DIR from their arguments, the work folder made and entered, the vehicle's key made afresh
# from the passphrase (as a MAVLink ground station derives it), the LCM URL that stays on this
# machine.
source "$here/../integration/scaled_timeout.sh"
bin=$(cd "$1" && pwd) out=$2
mkdir -p "$out"
cd "$out"
rm -f uav.key uav.key.last
"$bin/uav-keygen" uav.key --passphrase "$passphrase" > /dev/null
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
